// tmpc check --controller FILE.tmpc --scenario FILE [--json]: whether the scenario's
// trajectory is inside the artifact's envelope (acceleration box, speed, yaw) and its
// feedforward inside the range the input box was tightened for, every period of the
// flight; exit code 1 with the first time and the numbers when it is not. A flyable
// trajectory's forces on the load are then checked against the state box
// (force_envelope.hpp): a warning, not a refusal, when no controller can hold them.
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "data_files.hpp"
#include "tmpc/runtime/force_envelope.hpp"
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
  const ForceEnvelopeReport f = r.ok ? check_force_envelope(a, *sc.trajectory, sc.disturbances, sc.duration) : ForceEnvelopeReport{};
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
    if (f.applicable) {
      nlohmann::json w = nlohmann::json::array();
      nlohmann::json wy = nlohmann::json::array();
      for (const ForceWindow& c : f.certified) w.push_back({c.start, c.end});
      for (const ForceWindow& c : f.certified_reference_yaw) wy.push_back({c.start, c.end});
      j["forces"] = {{"message", f.message},           {"static_peak", f.static_peak},
                     {"static_peak_state", f.static_peak_state}, {"static_peak_time", f.static_peak_time},
                     {"static_outside_s", f.static_outside},   {"static_peak_best_yaw", f.static_peak_best_yaw},
                     {"static_peak_best_yaw_time", f.static_peak_best_yaw_time},
                     {"static_outside_best_yaw_s", f.static_outside_best_yaw}, {"certified_windows", w},
                     {"certified_windows_reference_yaw", wy}};
    }
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s: %s\n", r.ok ? "flyable" : "REFUSED", r.message.c_str());
    if (f.applicable) std::printf("%s%s\n", f.certified.empty() ? "" : "WARNING: ", f.message.c_str());
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
