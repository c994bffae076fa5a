// The real-time processes:
//   tmpc controller --controller FILE.tmpc --port DEV [--scenario FILE] [--baud] [--solver] [--rt-priority]
//                   [--cpu] [--duration] [--telemetry FILE] [--no-join] [--yaw-into-force]
//                   [estimator flags: --observer, --observer-gain, --fixed-filter-gain, --no-innovation-gate,
//                    --no-step-detection, --step-keeps-lift]                 the on-board program
//   tmpc plant --config FILE --port DEV [--scenario FILE] [--baud] [--duration] [--no-disturbance] [--run K]
//                                                         the scenario's plant over serial
//   tmpc hil --controller FILE.tmpc [--scenario FILE] [--config FILE] [--solver] [--duration] [--out DIR] [--no-join]
//            [--yaw-into-force] [the controller's estimator flags]
//                                                         both, over a pseudo-terminal pair
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "data_files.hpp"
#include "estimator_flags.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/runtime/controller_loop.hpp"
#include "tmpc/runtime/plant_loop.hpp"
#include "tmpc/runtime/preflight.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc::cli {

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

void install_signals() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}


void print_controller(const ControllerLoopStats& s) {
  for (const std::string& m : s.realtime.not_set) std::fprintf(stderr, "tmpc controller: not set: %s\n", m.c_str());
  std::printf("controller: %ld periods, %ld with a state; optimizer used %ld, late %ld, busy %ld -> fallback %ld; "
              "safe command %ld (watchdog %d periods); clipped %ld; %ld period boundaries slept through; "
              "%ld law restarts\n",
              s.periods, s.states, s.optimizer_used, s.late, s.busy, s.fallback_periods, s.safe_periods,
              s.watchdog_periods, s.clipped_periods, s.skipped, s.restarts);
  std::printf("  deadline misses: %ld (late %ld + busy %ld + skipped %ld)\n", s.late + s.busy + s.skipped, s.late, s.busy,
              s.skipped);
  std::printf("  wake-up latency p99 %.1f us, max %.1f us (%ld periods over half a period); period jitter max %.1f us; "
              "solve p50 %.1f us, max %.1f us\n",
              s.wake_latency_p99_us, s.wake_latency_max_us, s.late_wakes, s.period_jitter_max_us, s.solve_p50_us,
              s.solve_max_us);
  std::printf("  link (session %08x, plant %08x): states %s; %ld send failures; telemetry %llu records, %llu dropped\n",
              s.session, s.peer_session, io::summary(s.link).c_str(), s.send_failures, s.telemetry_records,
              s.telemetry_dropped);
}

void print_plant(const PlantLoopStats& s) {
  std::printf("plant: %ld periods, %ld without a control (%ld held the last input, %ld on the safe command after %ld "
              "link loss(es)%s); RMSE of the first three states %.4f, %.4f, %.4f; max position error %.3f m%s\n",
              s.periods, s.periods_without_control, s.held_periods, s.safe_command_periods, s.link_losses,
              s.first_link_loss_s >= 0.0 ? (", first at " + std::to_string(s.first_link_loss_s) + " s").c_str() : "",
              s.rmse.size() > 0 ? s.rmse[0] : 0.0, s.rmse.size() > 1 ? s.rmse[1] : 0.0, s.rmse.size() > 2 ? s.rmse[2] : 0.0,
              s.max_position_error, s.diverged ? ", DIVERGED" : "");
  std::printf("  link (session %08x, controller %08x, %ld controller session(s)): controls %s (%ld fallback, %ld safe)\n",
              s.session, s.peer_session, s.controller_sessions, io::summary(s.link).c_str(), s.fallback_frames,
              s.safe_frames);
}

/// Link counts by reason for metrics.json.
nlohmann::json link_json(const io::LinkCounts& c) {
  nlohmann::json j;
  j["accepted"] = c.accepted;
  j["rejected"] = c.rejected_total();
  for (std::size_t i = 0; i < io::kRejectReasons; ++i) j["rejected_by_reason"][io::to_string(static_cast<io::Reject>(i))] = c.rejected[i];
  j["lost"] = c.lost;
  j["session_changes"] = c.session_changes;
  j["resyncs"] = c.resyncs;
  return j;
}

struct RtCli {
  std::string controller, config, scenario = kDefaultScenario, port, solver = "auto", explicit_law, telemetry,
      out = "out/hil", plant, tube_law;
  int baud = 921600, priority = 0, cpu = -1, run = -1;
  long seed = -1;
  double duration = 0.0;
  bool no_disturbance = false, no_join = false, yaw_into_force = false;
  EstimatorChoice estimator;
};

Scenario scenario_of(const RtCli& o) {
  Scenario sc = load_scenario(data_file(o.scenario));
  if (o.no_disturbance) sc.disturbances = DisturbanceProfile{};
  return sc;
}

ControllerLoopOptions controller_options(const RtCli& o, const ControllerArtifact& a, const Scenario& sc) {
  ControllerLoopOptions c;
  // Before any flight: the trajectory inside the artifact's envelope.
  require_flight(a, *sc.trajectory, o.duration > 0.0 ? std::min(o.duration, sc.duration) : sc.duration,
                 "scenario " + sc.name);
  c.trajectory = sc.trajectory;
  c.solver = resolve_solver(o.solver, a, o.tube_law, c.deadline_fraction, "tmpc controller", &c.solver_note);
  c.tube_law = o.tube_law;
  c.estimator = o.estimator;
  c.reference_join = !o.no_join;
  c.yaw_into_force = o.yaw_into_force;
  c.explicit_law = o.explicit_law.empty() ? explicit_path_for(o.controller) : o.explicit_law;
  c.duration_s = o.duration;
  c.realtime.priority = o.priority;
  c.realtime.cpu = o.cpu;
  c.telemetry_csv = o.telemetry;
  return c;
}

void run_controller(const RtCli& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  const Scenario sc = scenario_of(o);
  ControllerLoopOptions c = controller_options(o, a, sc);
  io::SerialOpenReport rep;
  auto port = io::open_serial(o.port, o.baud, &rep);
  if (!rep.note.empty()) std::fprintf(stderr, "tmpc controller: %s: %s\n", o.port.c_str(), rep.note.c_str());
  install_signals();
  print_controller(run_controller_loop(a, *port, c, g_stop));
}

PlantLoopOptions plant_options(const RtCli& o, double duration) {
  PlantLoopOptions p;
  p.plant = o.plant;
  p.run = o.run;
  p.seed = o.seed;
  p.duration_s = duration;
  return p;
}

void run_plant(const RtCli& o) {
  if (o.config.empty()) throw std::runtime_error("tmpc plant: give the design config of the plant (--config FILE)");
  const Config cfg = load_config(data_file(o.config));
  const Scenario sc = scenario_of(o);
  io::SerialOpenReport rep;
  auto port = io::open_serial(o.port, o.baud, &rep);
  install_signals();
  print_plant(run_plant_loop(PlantSetup::from_config(cfg), sc, *port,
                             plant_options(o, o.duration > 0.0 ? std::min(o.duration, sc.duration) : sc.duration), g_stop));
}

void run_hil(const RtCli& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  const Scenario sc = scenario_of(o);
  // The plant: the artifact's vehicle, or --config's (a plant other than designed for).
  PlantSetup setup = PlantSetup::from_artifact(a);
  if (!o.config.empty()) {
    const Config cfg = load_config(data_file(o.config));
    if (cfg.model != a.model) throw std::runtime_error(o.config + ": its model is not the artifact's");
    setup.model.vehicle = cfg.vehicle;
  }
  const double duration = o.duration > 0.0 ? std::min(o.duration, sc.duration) : sc.duration;
  RtCli co = o;
  if (co.telemetry.empty()) co.telemetry = o.out + "/telemetry.csv";
  co.duration = duration + 0.1;  // the controller outlives the plant by a few periods
  ControllerLoopOptions c = controller_options(co, a, sc);
  c.duration_s = co.duration;
  io::PtyPair pty = io::open_pty_pair();
  auto port = io::open_serial(pty.slave_path, o.baud);
  std::filesystem::create_directories(o.out);
  install_signals();
  PlantLoopStats ps;
  // The plant starts once the controller is ready: its start-up (the law, the solver
  // thread) read as silence on the link held the plant's input for the first 8 periods
  // and, once, declared the link lost at 0.1 s.
  std::atomic<bool> ready{false};
  c.ready = &ready;
  std::thread plant([&] {
    while (!ready.load() && !g_stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!g_stop.load()) ps = run_plant_loop(setup, sc, *pty.master, plant_options(o, duration), g_stop);
  });
  ControllerLoopStats cs;
  try {
    cs = run_controller_loop(a, *port, c, g_stop);
  } catch (...) {
    g_stop.store(true);
    plant.join();
    throw;
  }
  plant.join();
  std::printf("hil over %s, scenario %s, %.1f s, solver %s, observer %s%s\n", pty.slave_path.c_str(), sc.name.c_str(),
              duration, c.solver.c_str(), cs.observer.c_str(), sc.disturbances.empty() ? ", no disturbance" : "");
  print_plant(ps);
  print_controller(cs);
  nlohmann::json j;
  for (std::size_t i = 0; i < ps.rmse.size(); ++i) j["rmse"][a.state_names[i]] = ps.rmse[i];
  j["solver"] = {{"name", c.solver}, {"why", c.solver_note}};
  j["estimator"] = cs.observer;
  j["periods"] = cs.periods;
  // Every period without the optimizer's answer in time: late, still busy with an
  // abandoned solve, or slept through entirely.
  j["deadline_misses"] = cs.late + cs.busy + cs.skipped;
  j["late_periods"] = cs.late;
  j["busy_periods"] = cs.busy;
  j["skipped_periods"] = cs.skipped;
  j["fallback_periods"] = cs.fallback_periods;
  j["reverted_periods"] = cs.reverted_periods;
  j["safe_periods"] = cs.safe_periods;
  j["clipped_periods"] = cs.clipped_periods;
  j["solve_us"] = {{"p50", cs.solve_p50_us}, {"max", cs.solve_max_us}};
  j["wake_latency_us"] = {{"p99", cs.wake_latency_p99_us}, {"max", cs.wake_latency_max_us}};
  j["late_wakes"] = cs.late_wakes;
  j["link"] = {{"states", link_json(cs.link)}, {"controls", link_json(ps.link)}};
  j["plant"] = {{"held_periods", ps.held_periods}, {"safe_command_periods", ps.safe_command_periods},
                {"link_losses", ps.link_losses}, {"first_link_loss_s", ps.first_link_loss_s}};
  j["law_restarts"] = cs.restarts;
  j["telemetry"] = {{"records", cs.telemetry_records}, {"dropped", cs.telemetry_dropped}};
  j["diverged"] = ps.diverged;
  std::ofstream(o.out + "/metrics.json") << j.dump(2) << "\n";
  std::printf("  %s/metrics.json, %s\n", o.out.c_str(), co.telemetry.c_str());
}

void common(CLI::App* s, RtCli& o) {
  s->add_option("--baud", o.baud, "serial baud rate (default 921600)");
  s->add_option("--duration", o.duration, "seconds (default: controller until SIGINT; plant and hil: the scenario's)")
      ->check(CLI::PositiveNumber);
  s->add_option("--scenario", o.scenario, "scenario file (default: " + std::string(kDefaultScenario) + ")");
}

}  // namespace

void register_realtime(CLI::App& app) {
  auto c = std::make_shared<RtCli>();
  CLI::App* sc = app.add_subcommand("controller", "The on-board controller over a serial port (real time)");
  sc->add_option("--controller", c->controller, "controller artifact")->required()->check(CLI::ExistingFile);
  sc->add_option("--port", c->port, "serial device")->required();
  sc->add_option("--solver", c->solver, flight_solver_help())->check(CLI::IsMember(flight_solver_choices()));
  sc->add_option("--explicit", c->explicit_law, "explicit law (default: CONTROLLER + 'x')");
  sc->add_option("--tube-law", c->tube_law, "tube law, overriding the artifact's")
      ->check(CLI::IsMember({"mayne", "offset-free"}));
  sc->add_option("--rt-priority", c->priority, "SCHED_FIFO priority 1..99 (0: none)")->check(CLI::Range(0, 99));
  sc->add_option("--cpu", c->cpu, "pin the loop to this CPU");
  sc->add_option("--telemetry", c->telemetry, "telemetry CSV to write");
  sc->add_flag("--no-join", c->no_join, "a start off the reference straight to it, without the reference join");
  sc->add_flag("--yaw-into-force", c->yaw_into_force, kYawIntoForceHelp);
  add_estimator_flags(sc, c->estimator);
  common(sc, *c);
  sc->callback([c]() { run_controller(*c); });

  auto p = std::make_shared<RtCli>();
  CLI::App* sp = app.add_subcommand("plant", "The nonlinear plant in real time over a serial port");
  sp->add_option("--config", p->config, "design configuration of the plant (YAML)")->required()->check(CLI::ExistingFile);
  sp->add_option("--port", p->port, "serial device")->required();
  sp->add_option("--plant", p->plant, "el | mujoco (default: the scenario's)")->check(CLI::IsMember({"el", "mujoco"}));
  sp->add_flag("--no-disturbance", p->no_disturbance, "without the scenario's disturbances");
  sp->add_option("--run", p->run, "Monte Carlo run index (masses and inertias drawn per the scenario)");
  sp->add_option("--seed", p->seed, "Monte Carlo seed (default: the scenario's)");
  common(sp, *p);
  sp->callback([p]() { run_plant(*p); });

  auto h = std::make_shared<RtCli>();
  CLI::App* sh = app.add_subcommand("hil", "Plant and controller in real time over a pseudo-terminal pair");
  sh->add_option("--config", h->config, "a design config whose vehicle the plant flies (default: the artifact's)")
      ->check(CLI::ExistingFile);
  sh->add_option("--controller", h->controller, "controller artifact")->required()->check(CLI::ExistingFile);
  sh->add_option("--solver", h->solver, flight_solver_help())->check(CLI::IsMember(flight_solver_choices()));
  sh->add_option("--explicit", h->explicit_law, "explicit law (default: CONTROLLER + 'x')");
  sh->add_option("--tube-law", h->tube_law, "tube law, overriding the artifact's")
      ->check(CLI::IsMember({"mayne", "offset-free"}));
  sh->add_option("--plant", h->plant, "el | mujoco (default: the scenario's)")->check(CLI::IsMember({"el", "mujoco"}));
  sh->add_flag("--no-disturbance", h->no_disturbance, "without the scenario's disturbances");
  sh->add_option("--run", h->run, "Monte Carlo run index");
  sh->add_option("--seed", h->seed, "Monte Carlo seed (default: the scenario's)");
  sh->add_option("--rt-priority", h->priority, "SCHED_FIFO priority of the controller loop")->check(CLI::Range(0, 99));
  sh->add_option("--out", h->out, "output directory (metrics.json, telemetry.csv)");
  sh->add_flag("--no-join", h->no_join, "a start off the reference straight to it, without the reference join");
  sh->add_flag("--yaw-into-force", h->yaw_into_force, kYawIntoForceHelp);
  add_estimator_flags(sh, h->estimator);
  common(sh, *h);
  sh->callback([h]() { run_hil(*h); });
}

}  // namespace tmpc::cli
