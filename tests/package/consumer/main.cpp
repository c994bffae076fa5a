// Uses the installed library: load the config, solve the hover equilibrium.
#include <cstdio>

#include "tmpc/model/config.hpp"
#include "tmpc/model/equilibrium.hpp"

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  const tmpc::Config cfg = tmpc::load_config(argv[1]);
  const tmpc::TiltrotorModel model(cfg.vehicle);
  const tmpc::Equilibrium eq = tmpc::solve_hover_equilibrium(model);
  std::printf("gamma_2 = %.5f rad, f_r = %.4f N\n", eq.angles(1), eq.u(0));
  return eq.residual < 1e-9 ? 0 : 1;
}
