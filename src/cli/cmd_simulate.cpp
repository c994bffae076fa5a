// tmpc simulate --controller FILE.tmpc [--scenario FILE] [--config FILE] [--solver] [--plant el|mujoco]
//   [--duration S] [--no-disturbance] [--run K | --monte-carlo K] [--seed S] [--reinit] [--no-join]
//   [--tube-law mayne|offset-free] [--observer-gain B] [--observer residual|kalman|switched] [--fixed-filter-gain]
//   [--no-innovation-gate] [--no-step-detection] [--step-keeps-lift]
//   [--yaw-into-force] --out DIR
// A scenario flown in-process on a virtual clock: telemetry.csv and metrics.json. The
// plant is the artifact's vehicle (or --config's: a plant other than the one designed
// for), scaled as the scenario says; the trajectory is checked against the envelope
// before take-off.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "commands.hpp"
#include "data_files.hpp"
#include "estimator_flags.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/metrics/campaign.hpp"
#include "tmpc/metrics/mission.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/runtime/force_envelope.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc::cli {

namespace {

struct SimOptions {
  std::string controller, config, scenario = kDefaultScenario, out = "out", solver = "auto", plant, explicit_law;
  double duration = 0.0;
  bool no_disturbance = false, reinit = false, no_join = false, yaw_into_force = false;
  std::string tube_law;
  EstimatorChoice estimator;
  int run = -1, monte_carlo = 0;
  long seed = -1;
};

/// "(-0.6, 0.5, -0.4)": the join's offset per position row.
std::string join_text(const std::vector<double>& g) {
  std::string t = "(";
  char buf[32];
  for (std::size_t i = 0; i < g.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%.3g", i ? ", " : "", g[i]);
    t += buf;
  }
  return t + ")";
}

void print_metrics(const MissionMetrics& r) {
  std::printf("  RMSE");
  for (std::size_t i = 0; i < std::min<std::size_t>(3, r.rmse.size()); ++i) {
    std::printf(" %s %.4f", r.state_names[i].c_str(), r.rmse[i]);
  }
  std::printf("; max |error|");
  for (std::size_t i = 0; i < std::min<std::size_t>(3, r.rmse.size()); ++i) {
    std::printf(" %s %.3f", r.state_names[i].c_str(), r.max_abs_error[i]);
  }
  std::printf("\n  periods %ld, fallbacks %ld, clipped %ld, state-constraint violations %ld, tube exits %ld%s\n",
              r.periods, r.fallback_periods, r.clipped_periods, r.state_constraint_violations, r.tube_exits,
              r.diverged ? ", DIVERGED" : "");
  if (r.reverted_periods > 0) {
    std::printf("  reverted to the tube gain's unconstrained law (tube_law.revert_beyond) in %ld of the fallback periods\n", r.reverted_periods);
  }
  std::printf("  solve time us: min %.1f, median %.1f, p99 %.1f, max %.1f; iterations mean %.1f, max %d\n",
              r.solve_min, r.solve_p50, r.solve_p99, r.solve_max, r.iterations_mean, r.iterations_max);
  if (r.state_constraint_violations > 0) {
    std::printf("  worst violation: %s at %.3f of its bound\n", r.violation_worst_state.c_str(), r.violation_max_ratio);
  }
  if (r.softened_periods > 0) {
    std::printf("  softened QP (hard QP infeasible) in %ld periods; largest slack %.4g in %s\n", r.softened_periods,
                r.slack_max, r.slack_worst_state.c_str());
  }
  if (r.yaw_governed_periods > 0) {
    std::printf("  yaw into the force: turned in %ld periods, up to %.3f rad from the mission's yaw\n",
                r.yaw_governed_periods, r.yaw_offset_max);
  }
  if (!r.join_offset.empty()) {
    std::printf("  reference join: from %s m off over %.2f s\n", join_text(r.join_offset).c_str(), r.join_duration);
  }
  if (r.offset_free) {
    std::printf("  observer: %s", r.estimator.c_str());
    if (r.estimator == "switched") {
      std::printf(" (the filter in %ld of %ld periods, %ld switches, noise level up to %.3g of the design's)",
                  r.filtered_periods, r.periods, r.observer_switches, r.noise_level_max);
    } else if (r.estimator == "kalman" && r.noise_level_max > 0.0) {
      std::printf(" (noise level up to %.3g of the design's)", r.noise_level_max);
    }
    if (r.filter_louder_periods > 0) {
      std::printf("; its gain for up to %.0f times the design's noise in %ld periods", r.filter_noise_scale_max,
                  r.filter_louder_periods);
    }
    if (r.gated_samples > 0) std::printf("; %ld glitched samples replaced by the filter's prediction", r.gated_samples);
    if (r.step_detections > 0) std::printf("; %ld disturbance steps detected", r.step_detections);
    if (r.step_lift_reopenings > 0) std::printf(" (%ld re-opened the lift)", r.step_lift_reopenings);
    if (r.step_actuator_corrections > 0) std::printf(" (%ld read as the actuators')", r.step_actuator_corrections);
    if (r.step_late_kept > 0) std::printf("; %ld older than the detection window, left to the steady gain", r.step_late_kept);
    std::printf("\n");
  }
  if (r.tube_exits > 0) {
    std::printf("  tube exits per window:");
    for (std::size_t w = 0; w < r.tube_exits_per_step.size(); ++w) {
      std::printf(" from %.0f s: %ld (up to %.3g radii of Z, back by %.2f s)", r.window_starts[w], r.tube_exits_per_step[w],
                  r.tube_ratio_max_per_step[w], r.tube_settle_s_per_step[w]);
    }
    std::printf("; mostly in %s\n", r.tube_worst_state.c_str());
  }
}

// --monte-carlo K: K runs with masses and inertias drawn per the scenario's
// plant.random (run index 0..K-1), each in OUT/run_K/, the campaign in OUT/metrics.json.
void run_campaign(const SimOptions& o, const ControllerArtifact& a, const Scenario& sc, MissionOptions m) {
  std::vector<MissionMetrics> runs;
  const unsigned seed = o.seed >= 0 ? static_cast<unsigned>(o.seed) : sc.plant.random.seed;
  if (!(sc.plant.random.fraction > 0.0)) {
    std::fprintf(stderr, "tmpc simulate: note: scenario %s has no plant.random fraction: every run flies the same plant\n",
                 sc.source.c_str());
  }
  m.seed = seed;
  std::printf("Monte Carlo: %d runs of %s, masses and inertias +-%.0f %% (%s, seed %u), solver %s\n", o.monte_carlo,
              sc.name.c_str(), 100.0 * sc.plant.random.fraction, sc.plant.random.distribution.c_str(), seed,
              m.solver.c_str());
  for (int k = 0; k < o.monte_carlo; ++k) {
    const std::string dir = o.out + "/run_" + std::to_string(k);
    std::filesystem::create_directories(dir);
    m.run = k;
    m.telemetry_csv = dir + "/telemetry.csv";
    std::fprintf(stderr, "\r  run %d/%d ...", k + 1, o.monte_carlo);
    runs.push_back(run_mission(a, sc, m));
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
  Scenario sc = load_scenario(data_file(o.scenario));
  if (o.no_disturbance) sc.disturbances = DisturbanceProfile{};
  std::filesystem::create_directories(o.out);
  VehicleParams plant_vehicle;
  MissionOptions m;
  if (!o.config.empty()) {
    const Config plant_cfg = load_config(data_file(o.config));
    if (plant_cfg.model != a.model) throw std::runtime_error(o.config + ": its model is not the artifact's");
    plant_vehicle = plant_cfg.vehicle;
    m.plant_vehicle = &plant_vehicle;
  }
  m.solver = resolve_solver(o.solver, a, o.tube_law, 0.8, "tmpc simulate");
  m.plant = o.plant;
  m.duration = o.duration;
  m.run = o.run;
  m.reinitialize_nominal = o.reinit;
  m.reference_join = !o.no_join;
  m.yaw_into_force = o.yaw_into_force;
  m.tube_law = o.tube_law;
  m.estimator = o.estimator;
  m.telemetry_csv = o.out + "/telemetry.csv";
  m.explicit_law = o.explicit_law.empty() ? explicit_path_for(o.controller) : o.explicit_law;
  m.seed = o.seed;
  if (o.monte_carlo > 0) {
    run_campaign(o, a, sc, m);
    return;
  }
  if (o.run < 0 && sc.plant.random.fraction > 0.0) {  // a single flight flies the nominal plant
    std::fprintf(stderr,
                 "tmpc simulate: note: scenario %s draws masses and inertias +-%.0f %% only per Monte Carlo run "
                 "(--run K or --monte-carlo K): this flight flies the nominal plant\n",
                 sc.source.c_str(), 100.0 * sc.plant.random.fraction);
  }
  const MissionMetrics r = run_mission(a, sc, m);
  std::ofstream(o.out + "/metrics.json") << metrics_json(r) << "\n";
  const double duration = o.duration > 0.0 ? std::min(o.duration, sc.duration) : sc.duration;
  std::printf("scenario %s (%s), %.0f s, plant %s%s, solver %s, %s tube law%s%s%s\n", sc.name.c_str(),
              sc.trajectory->description().c_str(), duration, r.plant.c_str(), o.config.empty() ? "" : (" of " + o.config).c_str(),
              m.solver.c_str(), r.offset_free ? "offset-free" : "Mayne's",
              sc.disturbances.empty() ? ", no disturbance" : (", " + std::to_string(sc.disturbances.events().size()) + " disturbance events").c_str(),
              r.noisy ? ", noisy sensors" : "", o.run >= 0 ? (", Monte Carlo run " + std::to_string(o.run)).c_str() : "");
  print_metrics(r);
  if (a.model == ModelKind::Tiltrotor) {  // whether any controller could have held the forces (the plant's load)
    const VehicleParams flown = sc.plant_vehicle(m.plant_vehicle ? *m.plant_vehicle : a.vehicle, o.run, o.seed);
    const ForceEnvelopeReport f = check_force_envelope(a, *sc.trajectory, sc.disturbances, duration, &flown);
    if (f.applicable) std::printf("  %s\n", f.message.c_str());
  }
  std::printf("  %s/metrics.json, %s/telemetry.csv\n", o.out.c_str(), o.out.c_str());
}

}  // namespace

void register_simulate(CLI::App& app) {
  auto o = std::make_shared<SimOptions>();
  CLI::App* sub = app.add_subcommand("simulate", "Fly a scenario in simulation on a virtual clock");
  sub->add_option("--controller", o->controller, "controller artifact")->required();
  sub->add_option("--scenario", o->scenario, "scenario file (default: " + std::string(kDefaultScenario) + ")");
  sub->add_option("--config", o->config, "a design config whose vehicle the plant flies (default: the artifact's)")
      ->check(CLI::ExistingFile);
  sub->add_option("--solver", o->solver, flight_solver_help())->check(CLI::IsMember(flight_solver_choices()));
  sub->add_option("--explicit", o->explicit_law, "explicit law for --solver explicit (default: CONTROLLER + 'x')");
  sub->add_option("--plant", o->plant, "el | mujoco (default: the scenario's)")->check(CLI::IsMember({"el", "mujoco"}));
  sub->add_option("--duration", o->duration, "seconds (at most the scenario's)")->check(CLI::PositiveNumber);
  sub->add_flag("--no-disturbance", o->no_disturbance, "without the scenario's disturbances");
  sub->add_option("--run", o->run, "Monte Carlo run index (masses and inertias drawn per the scenario)");
  sub->add_option("--monte-carlo", o->monte_carlo, "K drawn runs (thesis: 10), campaign metrics in OUT/metrics.json")
      ->check(CLI::Range(1, 100000));
  sub->add_option("--seed", o->seed, "Monte Carlo seed (default: the scenario's plant.random.seed)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--reinit", o->reinit, "re-initialise the nominal state to the measured error when admissible");
  sub->add_flag("--yaw-into-force", o->yaw_into_force, kYawIntoForceHelp);
  sub->add_flag("--no-join", o->no_join, "fly a start off the reference without the reference join (straight to the mission's reference)");
  sub->add_option("--tube-law", o->tube_law, "tube law, overriding the artifact's")
      ->check(CLI::IsMember({"mayne", "offset-free"}));
  add_estimator_flags(sub, o->estimator);
  sub->add_option("--out", o->out, "output directory");
  sub->callback([o]() { run_simulate(*o); });
}

}  // namespace tmpc::cli
