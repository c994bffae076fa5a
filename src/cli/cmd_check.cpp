// tmpc check --controller FILE.tmpc --scenario FILE [--json]: whether the scenario's
// trajectory is inside the artifact's envelope (acceleration box, speed, yaw) and its
// feedforward inside the range the input box was tightened for, every period of the
// flight; exit code 1 with the first time and the numbers when it is not.
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "data_files.hpp"
#include "tmpc/runtime/preflight.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc::cli {

namespace {

struct CheckOptions {
  std::string controller, scenario;
  bool json = false;
};

int run_check(const CheckOptions& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  const Scenario sc = load_scenario(data_file(o.scenario));
  const PreflightReport r = check_flight(a, *sc.trajectory, sc.duration);
  if (o.json) {
    nlohmann::json j;
    j["ok"] = r.ok;
    j["message"] = r.message;
    j["scenario"] = sc.name;
    j["duration"] = sc.duration;
    if (!r.ok) j["time"] = r.time;
    j["acceleration_min"] = {r.acceleration_min(0), r.acceleration_min(1), r.acceleration_min(2)};
    j["acceleration_max"] = {r.acceleration_max(0), r.acceleration_max(1), r.acceleration_max(2)};
    j["speed_max"] = r.speed_max;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s: %s\n", r.ok ? "flyable" : "REFUSED", r.message.c_str());
  }
  return r.ok ? 0 : 1;
}

}  // namespace

void register_check(CLI::App& app) {
  auto o = std::make_shared<CheckOptions>();
  CLI::App* sub = app.add_subcommand("check", "Check a scenario's trajectory against an artifact's envelope");
  sub->add_option("--controller", o->controller, "controller artifact")->required()->check(CLI::ExistingFile);
  sub->add_option("--scenario", o->scenario, "scenario file")->required()->check(CLI::ExistingFile);
  sub->add_flag("--json", o->json, "print JSON");
  sub->callback([o]() {
    const int rc = run_check(*o);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace tmpc::cli
