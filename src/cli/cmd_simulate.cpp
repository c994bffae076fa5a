// tmpc simulate --config FILE --controller FILE.tmpc [--solver] [--plant el|mujoco] [--monte-carlo K --seed S]
//   [--duration 80] [--no-disturbance] [--run K] [--reinit] [--tube-law mayne|offset-free] [--observer-gain B] --out DIR
// The helix mission in-process on a virtual clock: telemetry.csv and metrics.json.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "commands.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/metrics/campaign.hpp"
#include "tmpc/metrics/mission.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc::cli {

namespace {

struct SimOptions {
  std::string controller, config, out = "out", solver = "admm", plant = "el", explicit_law;
  double duration = 80.0;
  bool no_disturbance = false, reinit = false;
  std::string tube_law;
  double observer_gain = 0.0;
  int run = -1, monte_carlo = 0;
  long seed = -1;
};

void print_metrics(const MissionMetrics& r) {
  std::printf("  RMSE x %.4f m, y %.4f m, z %.4f m, psi %.5f rad; max |error| x %.3f y %.3f z %.3f m\n", r.rmse[0],
              r.rmse[1], r.rmse[2], r.rmse[5], r.max_abs_error[0], r.max_abs_error[1], r.max_abs_error[2]);
  std::printf("  periods %ld, fallbacks %ld, clipped %ld, state-constraint violations %ld, tube exits %ld%s\n",
              r.periods, r.fallback_periods, r.clipped_periods, r.state_constraint_violations, r.tube_exits,
              r.diverged ? ", DIVERGED" : "");
  std::printf("  solve time us: min %.1f, median %.1f, p99 %.1f, max %.1f; iterations mean %.1f, max %d\n",
              r.solve_min, r.solve_p50, r.solve_p99, r.solve_max, r.iterations_mean, r.iterations_max);
  if (r.tube_exits > 0) {
    std::printf("  tube exits per disturbance window:");
    for (std::size_t w = 0; w < r.tube_exits_per_step.size(); ++w) {
      std::printf(" %ld (up to %.3g radii of Z, back by %.2f s)", r.tube_exits_per_step[w], r.tube_ratio_max_per_step[w],
                  r.tube_settle_s_per_step[w]);
    }
    std::printf("; mostly in %s\n", r.tube_worst_state.c_str());
  }
}

// --monte-carlo K: K runs with masses and inertias perturbed (run index 0..K-1 of the
// seeded distribution), each in OUT/run_K/, the campaign in OUT/metrics.json.
void run_campaign(const SimOptions& o, const ControllerArtifact& a, MissionOptions m) {
  std::vector<MissionMetrics> runs;
  const Config cfg = load_config_from_string(a.config_text, o.controller);
  const unsigned seed = o.seed >= 0 ? static_cast<unsigned>(o.seed) : cfg.perturbation.seed;
  m.seed = seed;
  std::printf("Monte Carlo: %d runs, masses and inertias +-%.0f %% (%s, seed %u), %.0f s each, solver %s\n",
              o.monte_carlo, 100.0 * cfg.perturbation.fraction, cfg.perturbation.distribution.c_str(), seed,
              o.duration, o.solver.c_str());
  for (int k = 0; k < o.monte_carlo; ++k) {
    const std::string dir = o.out + "/run_" + std::to_string(k);
    std::filesystem::create_directories(dir);
    m.run = k;
    m.telemetry_csv = dir + "/telemetry.csv";
    std::fprintf(stderr, "\r  run %d/%d ...", k + 1, o.monte_carlo);
    runs.push_back(run_mission(a, m));
    std::ofstream(dir + "/metrics.json") << metrics_json(runs.back()) << "\n";
  }
  std::fprintf(stderr, "\r");
  std::ofstream(o.out + "/metrics.json") << campaign_json(runs, seed) << "\n";
  for (int k = 0; k < o.monte_carlo; ++k) {
    std::printf("run %d:\n", k);
    print_metrics(runs[static_cast<std::size_t>(k)]);
  }
  std::printf("  %s/metrics.json (campaign), %s/run_K/\n", o.out.c_str(), o.out.c_str());
}

void run_simulate(const SimOptions& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  std::filesystem::create_directories(o.out);
  MissionOptions m;
  m.solver = o.solver;
  m.plant = o.plant;
  m.duration = o.duration;
  m.disturbance = !o.no_disturbance;
  m.run = o.run;
  m.reinitialize_nominal = o.reinit;
  m.tube_law = o.tube_law;
  m.observer_gain = o.observer_gain;
  m.telemetry_csv = o.out + "/telemetry.csv";
  m.explicit_law = o.explicit_law.empty() ? explicit_path_for(o.controller) : o.explicit_law;
  m.seed = o.seed;
  if (o.monte_carlo > 0) {
    run_campaign(o, a, m);
    return;
  }
  const MissionMetrics r = run_mission(a, m);
  std::ofstream(o.out + "/metrics.json") << metrics_json(r) << "\n";
  std::printf("helix mission, %.0f s, plant %s, solver %s, %s tube law%s%s\n", o.duration, o.plant.c_str(),
              o.solver.c_str(), r.offset_free ? "offset-free" : "Mayne's", m.disturbance ? ", 1 N steps at 20/40/60 s" : ", no disturbance",
              o.run >= 0 ? (", Monte Carlo run " + std::to_string(o.run)).c_str() : "");
  print_metrics(r);
  std::printf("  %s/metrics.json, %s/telemetry.csv\n", o.out.c_str(), o.out.c_str());
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto o = std::make_shared<SimOptions>();
  CLI::App* sub = app.add_subcommand("simulate", "Closed-loop helix mission on a virtual clock");
  sub->add_option("--controller", o->controller, "controller artifact")->required();
  sub->add_option("--config", o->config, "accepted for symmetry; the artifact carries its configuration");
  sub->add_option("--solver", o->solver, solver_choices_help())->check(CLI::IsMember(solver_choices()));
  sub->add_option("--explicit", o->explicit_law, "explicit law for --solver explicit (default: CONTROLLER + 'x')");
  sub->add_option("--plant", o->plant, "el | mujoco")->check(CLI::IsMember({"el", "mujoco"}));
  sub->add_option("--duration", o->duration, "seconds")->check(CLI::PositiveNumber);
  sub->add_flag("--no-disturbance", o->no_disturbance, "without the 1 N steps");
  sub->add_option("--run", o->run, "Monte Carlo run index (masses and inertias perturbed)");
  sub->add_option("--monte-carlo", o->monte_carlo, "K perturbed runs (thesis: 10), campaign metrics in OUT/metrics.json")
      ->check(CLI::Range(1, 100000));
  sub->add_option("--seed", o->seed, "perturbation seed (default: the config's perturbation.seed)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--reinit", o->reinit, "re-initialise the nominal state to the measured error when admissible");
  sub->add_option("--tube-law", o->tube_law, "tube law, overriding the config's tube_law.offset_free")
      ->check(CLI::IsMember({"mayne", "offset-free"}));
  sub->add_option("--observer-gain", o->observer_gain, "offset-free observer gain beta in (0, 1] (default: the config's)")
      ->check(CLI::Range(1e-6, 1.0));
  sub->add_option("--out", o->out, "output directory");
  sub->callback([o]() { run_simulate(*o); });
}

}  // namespace tmpc::cli
