// tmpc: tube MPC for the tiltrotor with a suspended load. One executable, subcommands.
#include <cstdio>
#include <exception>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#ifdef TMPC_HAVE_CUDA
#include "cuda_qp_solver.hpp"
#endif
#include "tmpc/model/config.hpp"
#include "tmpc/synthesis/artifact.hpp"

int main(int argc, char** argv) {
#ifdef TMPC_HAVE_CUDA
  tmpc::register_cuda_solvers();  // "admm-cuda", "admm-cuda-thesis"
#endif
  CLI::App app{"tmpc: real-time tube MPC (design, simulation, control)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "tmpc 0.1.0");
  tmpc::cli::register_model(app);
  tmpc::cli::register_plant(app);
  tmpc::cli::register_design(app);
  tmpc::cli::register_solve(app);
  tmpc::cli::register_simulate(app);
  tmpc::cli::register_devices(app);
  tmpc::cli::register_explicit(app);
  tmpc::cli::register_compare(app);
  tmpc::cli::register_realtime(app);
  tmpc::cli::register_check(app);
  tmpc::cli::register_doctor(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {  // a command's verdict (tmpc check: refused), already printed
    return e.get_exit_code();              // (before ParseError, which it derives from)
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const tmpc::ArtifactError& e) {
    std::fprintf(stderr, "tmpc: file error: %s\n", e.what());
    return 2;
  } catch (const tmpc::ConfigError& e) {
    std::fprintf(stderr, "tmpc: configuration error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tmpc: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
