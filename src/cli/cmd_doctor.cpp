// `tmpc doctor [--port DEV] [--controller FILE] [--rt-priority P] [--cpu C] [--seconds S]
//              [--proc DIR] [--sys DIR]`: is this board ready for the real-time loop
// (runtime/doctor.hpp)? Exit status 1 when a finding is a failure, e.g. the measured
// wake-up latency and the solve time do not fit the controller's deadline.
#include <unistd.h>

#include <cstdio>
#include <stdexcept>

#include "commands.hpp"
#include "tmpc/runtime/doctor.hpp"
#include "tmpc/runtime/solver_choice.hpp"
#include "tmpc/runtime/tube_controller.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc::cli {

namespace {

struct DoctorCli {
  std::string port, controller, proc = "/proc", sys = "/sys";
  int priority = 80, cpu = -1;
  double seconds = 3.0;
};

int run_doctor(const DoctorCli& c) {
  DoctorOptions o;
  o.env.proc = c.proc;
  o.env.sys = c.sys;
  o.env.privileged = ::geteuid() == 0;
  o.port = c.port;
  o.rt_priority = c.priority;
  o.cpu = c.cpu;
  std::vector<Finding> findings = check_host(o);
  bool gpu = false;
  const std::vector<std::string> dev = device_lines(&gpu);
  findings.push_back({"gpu", gpu ? Severity::Ok : Severity::Info, dev.back(), ""});
  if (!c.controller.empty()) {
    const ControllerArtifact a = load_artifact(c.controller);
    o.period_s = a.sample_time;
    const SolverChoice ch = auto_solver(a, tube_law_options(a, "").offset_free, o.deadline_fraction);
    for (const SolverTiming& t : ch.timings) {
      if (t.name == ch.name) o.solve_p99_us = t.p99_us;
    }
    findings.push_back({"solver", Severity::Info, ch.name + " (--solver auto): " + ch.why, ""});
  }
  if (c.seconds > 0.0) {
    const LatencyRun r = measure_wakeup_latency(c.seconds, std::min(0.001, o.period_s), c.priority, c.cpu);
    findings.push_back(latency_verdict(r, o));
  }
  for (const Finding& f : findings) {
    std::printf("%-16s %-5s %s\n", f.check.c_str(), to_string(f.severity), f.found.c_str());
    if (!f.advice.empty()) std::printf("%-16s       -> %s\n", "", f.advice.c_str());
  }
  const bool ok = can_run(findings);
  std::printf("verdict: %s\n", ok ? "the controller can run here" : "the controller cannot meet its deadline or run here (FAIL above)");
  return ok ? 0 : 1;
}

}  // namespace

void register_doctor(CLI::App& app) {
  auto c = std::make_shared<DoctorCli>();
  CLI::App* sub = app.add_subcommand("doctor", "Check this board's real-time set-up for the controller");
  sub->add_option("--port", c->port, "serial device the controller will use");
  sub->add_option("--controller", c->controller, "controller artifact: its period, and its solver's calibrated time")
      ->check(CLI::ExistingFile);
  sub->add_option("--rt-priority", c->priority, "the controller's SCHED_FIFO priority (default 80)")->check(CLI::Range(1, 99));
  sub->add_option("--cpu", c->cpu, "the controller's CPU");
  sub->add_option("--seconds", c->seconds, "wake-up latency run (default 3; 0: none)")->check(CLI::NonNegativeNumber);
  sub->add_option("--proc", c->proc, "procfs root (default /proc)");
  sub->add_option("--sys", c->sys, "sysfs root (default /sys)");
  sub->callback([c]() {
    const int rc = run_doctor(*c);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace tmpc::cli
