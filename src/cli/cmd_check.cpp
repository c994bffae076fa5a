// tmpc check --controller FILE.tmpc --scenario FILE [--json]: whether the scenario's
// trajectory is inside the artifact's envelope (acceleration box, speed, yaw) and its
// feedforward inside the range the input box was tightened for, every period of the
// flight; exit code 1 with the first time and the numbers when it is not. A flyable
// trajectory's forces on the load are then checked against the state box
// (force_envelope.hpp): a warning, not a refusal, when no controller can hold them.
// --forces FILE writes the force on the load every period (world frame, the sample
// instants k T) with the reference's yaw, for scripts/best_case_peak.py --forces.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
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
  std::string controller, scenario, forces;
  bool json = false;
};

// t, the load force (N, world frame) and the reference's yaw (rad), one row a period.
void write_forces(const std::string& path, const ControllerArtifact& a, const Scenario& sc) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("--forces " + path + ": cannot open for writing");
  out << "t,f_x,f_y,f_z,psi_ref\n";
  out.precision(17);
  const long periods = std::lround(sc.duration / a.sample_time);
  for (long k = 0; k <= periods; ++k) {
    const double t = static_cast<double>(k) * a.sample_time;
    const Eigen::Vector3d f = sc.disturbances.load_force(t);
    out << t << ',' << f.x() << ',' << f.y() << ',' << f.z() << ',' << sc.trajectory->at(t).psi << '\n';
  }
  if (!out) throw std::runtime_error("--forces " + path + ": write failed");
}

int run_check(const CheckOptions& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  const Scenario sc = load_scenario(data_file(o.scenario));
  const PreflightReport r = check_flight(a, *sc.trajectory, sc.duration);
  if (!o.forces.empty()) write_forces(o.forces, a, sc);
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
      if (std::isfinite(f.yaw_window_min)) {
        j["forces"]["yaw_window"] = {{"width", f.yaw_window_min},
                                     {"time", f.yaw_window_time},
                                     {"first", f.yaw_window_first},
                                     {"last", f.yaw_window_last}};
      }
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
  sub->add_option("--forces", o->forces,
                  "write CSV t,f_x,f_y,f_z,psi_ref: the force on the load (N, world frame) and the reference's yaw every "
                  "period, for scripts/best_case_peak.py --forces");
  sub->callback([o]() {
    const int rc = run_check(*o);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace tmpc::cli
