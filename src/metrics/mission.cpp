// Closed-loop mission on a virtual clock (see mission.hpp).
#include "tmpc/metrics/mission.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tmpc/runtime/controller_solver.hpp"
#include "tmpc/runtime/plant_loop.hpp"
#include "tmpc/runtime/preflight.hpp"
#include "tmpc/runtime/reference_source.hpp"
#include "tmpc/runtime/tracking_error.hpp"
#include "tmpc/runtime/tube_controller.hpp"
#include "tmpc/runtime/yaw_governor.hpp"
#include "tmpc/sim/noise.hpp"
#include "tmpc/sim/plant_model.hpp"

namespace tmpc {

namespace {

/// A solver that hands every parameter it is given to a list, then solves.
class RecordingSolver final : public QpSolver {
 public:
  RecordingSolver(std::unique_ptr<QpSolver> inner, std::vector<Eigen::VectorXd>* out)
      : inner_(std::move(inner)), out_(out) {}
  const SolveResult& solve(const Eigen::VectorXd& x0) override {
    out_->push_back(x0);
    return inner_->solve(x0);
  }
  void reset() override { inner_->reset(); }
  const char* name() const override { return inner_->name(); }
  const ParametricQp& problem() const override { return inner_->problem(); }
  const SolverOptions& options() const override { return inner_->options(); }

 private:
  std::unique_ptr<QpSolver> inner_;
  std::vector<Eigen::VectorXd>* out_;
};


}  // namespace

MissionMetrics run_mission(const ControllerArtifact& a, const Scenario& sc, const MissionOptions& o) {
  const double duration = o.duration > 0.0 ? std::min(o.duration, sc.duration) : sc.duration;
  require_flight(a, *sc.trajectory, duration, "scenario " + sc.name);
  const int p = a.measured, m = a.m;
  SolverOptions so;
  so.eps_abs = so.eps_rel = a.solver.admm_epsilon;
  so.eta = a.solver.admm_eta;
  TubeControllerOptions to = flight_law_options(a, o.tube_law, o.estimator);
  to.reinitialize_nominal = o.reinitialize_nominal;
  std::unique_ptr<QpSolver> solver = make_controller_solver(o.solver, a, so, o.explicit_law, to.offset_free);
  if (o.record_qps != nullptr) solver = std::make_unique<RecordingSolver>(std::move(solver), o.record_qps);
  TubeController ctrl(a, std::move(solver), to);
  std::unique_ptr<YawGovernor> governor;
  std::shared_ptr<const Trajectory> flown = sc.trajectory;
  if (o.yaw_into_force) {  // the reference's yaw turned into the force (yaw_governor.hpp)
    governor = std::make_unique<YawGovernor>(yaw_governor_settings(a, *sc.trajectory, duration));
    flown = std::make_shared<GovernedTrajectory>(sc.trajectory, governor.get());
  }
  std::unique_ptr<ReferenceSource> reference = make_reference_source(a, flown);
  const std::vector<StateKind> kinds = a.measured_kinds();
  const int yaw_row = static_cast<int>(std::find(kinds.begin(), kinds.end(), StateKind::Yaw) - kinds.begin());
  Eigen::VectorXd x_r = Eigen::VectorXd::Zero(p), u_r = Eigen::VectorXd::Zero(m), measured = x_r;
  reference->at(0.0, x_r, u_r);
  PlantModel pm = PlantSetup::from_artifact(a).model;
  if (o.plant_vehicle != nullptr) pm.vehicle = *o.plant_vehicle;
  auto plant = make_scenario_plant(pm, sc, x_r, o.run, o.seed, o.plant);
  SensorNoise noise(sc.noise, kinds);

  MissionMetrics mm;
  mm.solver = o.solver;
  mm.plant = plant->name();
  mm.scenario = sc.name;
  mm.offset_free = to.offset_free;
  mm.estimator = to.offset_free ? to.observer : "none";
  mm.noisy = sc.noise.any();
  mm.state_names.assign(a.state_names.begin(), a.state_names.begin() + p);
  mm.input_names = a.input_names;
  mm.rmse.assign(static_cast<std::size_t>(p), 0.0);
  mm.max_abs_error.assign(static_cast<std::size_t>(p), 0.0);
  mm.tcv.assign(static_cast<std::size_t>(m), 0.0);
  mm.box_names = a.state_names;
  mm.box_peak_ratio.assign(static_cast<std::size_t>(a.n), 0.0);
  const double T = a.sample_time;
  const long K = std::lround(duration / T);
  TrackingError err(kinds, a.integrated), truth(kinds, a.integrated);
  if (o.reference_join) err.set_join(reference_join_settings(a));  // the law's error; the truth stays the mission's
  if (a.envelope.any_yaw()) {  // both in the reference's yaw frame, where the box bounds them
    err.set_yaw_frame(a.envelope.yaw);
    truth.set_yaw_frame(a.envelope.yaw);
  }
  Eigen::VectorXd u_prev = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd judged(a.n);
  std::vector<double> solve;
  solve.reserve(static_cast<std::size_t>(K));
  std::vector<double> sq(static_cast<std::size_t>(p), 0.0);
  mm.window_starts = {0.0};
  for (double t : sc.disturbances.event_times()) {
    if (t > 0.0 && t < duration) mm.window_starts.push_back(t);
  }
  for (const ActuatorFault& f : sc.faults) {  // a fault's onset opens a window too
    if (f.start > 0.0 && f.start < duration) mm.window_starts.push_back(f.start);
  }
  std::sort(mm.window_starts.begin(), mm.window_starts.end());
  mm.window_starts.erase(std::unique(mm.window_starts.begin(), mm.window_starts.end()), mm.window_starts.end());
  const std::size_t windows = mm.window_starts.size();
  mm.tube_exits_per_step.assign(windows, 0);
  mm.tube_ratio_max_per_step.assign(windows, 0.0);
  mm.tube_settle_s_per_step.assign(windows, 0.0);
  std::vector<long> worst_count(static_cast<std::size_t>(a.n), 0);
  std::ofstream csv;
  if (!o.telemetry_csv.empty()) {
    csv.open(o.telemetry_csv);
    if (!csv) throw std::runtime_error(o.telemetry_csv + ": cannot write the telemetry");
    csv << "t";
    for (int i = 0; i < p; ++i) csv << ",e_" << a.state_names[static_cast<std::size_t>(i)];
    for (int i = 0; i < p; ++i) csv << ",r_" << a.state_names[static_cast<std::size_t>(i)];
    for (const std::string& n : a.input_names) csv << ",u_" << n;
    for (const std::string& n : a.input_names) csv << ",ubar_" << n;
    csv << ",status,iterations,solve_us,fallback,clipped,in_tube,in_state_box,tube_ratio,tube_worst,softened,slack_max,filtered,noise_level";
    for (Eigen::Index i = 0; i < std::min<Eigen::Index>(3, a.D.cols()); ++i) csv << ",dhat_" << "xyz"[i];
    csv << ",gated,step\n";
  }
  const double box_limit = 10.0;
  bool filtered_before = false;
  for (long k = 0; k < K; ++k) {
    const double t = static_cast<double>(k) * T;
    if (!reference->at(t, x_r, u_r)) {
      mm.diverged = true;
      break;
    }
    const Eigen::VectorXd& xt_true = truth.update(plant->state(), x_r);
    measured = plant->state();
    noise.apply(measured);
    const Eigen::VectorXd& xt = err.update(measured, x_r);
    // What the box is judged on: the physical rows on the true state; the integral rows
    // on the controller's own integrators (they exist only there). The true integral of
    // a biased sensor's error grows without bound whatever the law does.
    judged = xt_true;
    judged.tail(a.n - p) = xt.tail(a.n - p);
    if (!judged.allFinite() || (a.N_x.cwiseProduct(judged).cwiseAbs().array() > box_limit).any()) {
      mm.diverged = true;
      break;
    }
    if (k == 0) ctrl.reset(xt);  // the nominal starts at the first measured error (a start offset)
    const ControlStep& s = ctrl.step(xt, u_r);
    if (governor && s.d_hat.size() >= 2) {
      governor->update(s.d_hat.head<2>(), x_r(yaw_row) - a.envelope.yaw, sc.trajectory->at(t).psi, T);
      mm.yaw_offset_max = std::max(mm.yaw_offset_max, std::abs(governor->offset()));
      mm.yaw_governed_periods += std::abs(governor->offset()) > 1e-3;
    }
    plant->advance(s.u, T);
    err.integrate(T);
    truth.integrate(T);
    ++mm.periods;
    for (int i = 0; i < p; ++i) {
      sq[static_cast<std::size_t>(i)] += xt_true(i) * xt_true(i);
      mm.max_abs_error[static_cast<std::size_t>(i)] = std::max(mm.max_abs_error[static_cast<std::size_t>(i)], std::abs(xt_true(i)));
    }
    if (k > 0) {
      for (int i = 0; i < m; ++i) mm.tcv[static_cast<std::size_t>(i)] += std::abs(s.u(i) - u_prev(i));
    }
    u_prev = s.u;
    if (to.offset_free) mm.d_hat_final.assign(s.d_hat.data(), s.d_hat.data() + s.d_hat.size());
    solve.push_back(s.solve_us);
    mm.iterations_mean += s.iterations;
    mm.iterations_max = std::max(mm.iterations_max, s.iterations);
    mm.fallback_periods += s.fallback;
    mm.reverted_periods += s.reverted;
    mm.clipped_periods += s.clipped;
    const Eigen::VectorXd ratio = a.N_x.cwiseProduct(judged).cwiseAbs();  // X is the unit box
    Eigen::Index vw = 0;
    const double vr = ratio.maxCoeff(&vw);
    for (Eigen::Index i = 0; i < a.n; ++i) {
      double& peak = mm.box_peak_ratio[static_cast<std::size_t>(i)];
      peak = std::max(peak, ratio(i));
    }
    if (vr > 1.0) {
      ++mm.state_constraint_violations;
      if (vr > mm.violation_max_ratio) {
        mm.violation_max_ratio = vr;
        mm.violation_worst_state = a.state_names[static_cast<std::size_t>(vw)];
      }
    }
    mm.filtered_periods += s.filtered;
    mm.observer_switches += k > 0 && s.filtered != filtered_before;
    filtered_before = s.filtered;
    mm.noise_level_max = std::max(mm.noise_level_max, s.noise_level);
    mm.gated_samples += s.gated_rows;
    if (s.step_detected) ++mm.step_detections;
    if (s.step_reopened_lift) ++mm.step_lift_reopenings;
    if (s.step_input) ++mm.step_actuator_corrections;
    if (s.step_late) ++mm.step_late_kept;
    mm.filter_louder_periods += s.filtered && s.filter_noise_scale > 1.0;
    if (s.filtered) mm.filter_noise_scale_max = std::max(mm.filter_noise_scale_max, s.filter_noise_scale);
    if (s.softened) {
      ++mm.softened_periods;
      if (s.slack_max > mm.slack_max) {
        mm.slack_max = s.slack_max;
        mm.slack_worst_state = a.state_names[static_cast<std::size_t>(s.slack_state)];
      }
    }
    std::size_t w = 0;  // the window of this period
    while (w + 1 < windows && t >= mm.window_starts[w + 1]) ++w;
    mm.tube_ratio_max_per_step[w] = std::max(mm.tube_ratio_max_per_step[w], s.tube_ratio);
    if (!s.in_tube) {
      ++mm.tube_exits;
      ++mm.tube_exits_per_step[w];
      mm.tube_settle_s_per_step[w] = t + T - mm.window_starts[w];
      ++worst_count[static_cast<std::size_t>(s.tube_worst)];
    }
    if (csv) {
      csv << t;
      for (int i = 0; i < p; ++i) csv << "," << xt_true(i);
      for (int i = 0; i < p; ++i) csv << "," << x_r(i);
      for (int i = 0; i < m; ++i) csv << "," << s.u(i);
      for (int i = 0; i < m; ++i) csv << "," << s.u_bar(i);
      csv << "," << to_string(s.status) << "," << s.iterations << "," << s.solve_us << "," << s.fallback << ","
          << s.clipped << "," << s.in_tube << "," << a.X.contains(a.N_x.cwiseProduct(judged)) << "," << s.tube_ratio
          << "," << s.tube_worst << "," << s.softened << "," << s.slack_max << "," << s.filtered << "," << s.noise_level;
      for (Eigen::Index i = 0; i < std::min<Eigen::Index>(3, s.d_hat.size()); ++i) csv << "," << s.d_hat(i);
      csv << "," << s.gated_rows << "," << step_code(s) << "\n";
    }
  }
  if (err.join().active()) {
    mm.join_offset.assign(err.join().offset().data(), err.join().offset().data() + err.join().offset().size());
    mm.join_duration = err.join().duration();
  }
  const auto most = std::max_element(worst_count.begin(), worst_count.end());
  if (mm.tube_exits > 0) mm.tube_worst_state = a.state_names[static_cast<std::size_t>(most - worst_count.begin())];
  const double n = std::max<double>(1.0, static_cast<double>(mm.periods));
  for (int i = 0; i < p; ++i) mm.rmse[static_cast<std::size_t>(i)] = std::sqrt(sq[static_cast<std::size_t>(i)] / n);
  mm.iterations_mean /= n;
  if (!solve.empty()) {
    std::sort(solve.begin(), solve.end());
    auto pct = [&](double q) { return solve[std::min(solve.size() - 1, static_cast<std::size_t>(q * solve.size()))]; };
    mm.solve_min = solve.front();
    mm.solve_max = solve.back();
    mm.solve_p50 = pct(0.5);
    mm.solve_p99 = pct(0.99);
    double sum = 0;
    for (double v : solve) sum += v;
    mm.solve_mean = sum / static_cast<double>(solve.size());
  }
  return mm;
}

std::string metrics_json(const MissionMetrics& m) {
  nlohmann::json j;
  nlohmann::json rmse, max_abs;
  auto name = [](const std::vector<std::string>& names, std::size_t i, const char* what) {
    return i < names.size() ? names[i] : std::string(what) + "_" + std::to_string(i);
  };
  for (std::size_t i = 0; i < m.rmse.size(); ++i) rmse[name(m.state_names, i, "state")] = m.rmse[i];
  for (std::size_t i = 0; i < m.max_abs_error.size(); ++i) max_abs[name(m.state_names, i, "state")] = m.max_abs_error[i];
  j["rmse"] = rmse;
  j["max_abs_error"] = max_abs;
  nlohmann::json tcv;
  for (std::size_t i = 0; i < m.tcv.size(); ++i) tcv[name(m.input_names, i, "input")] = m.tcv[i];
  j["tcv"] = tcv;
  j["solve_us"] = {{"min", m.solve_min}, {"mean", m.solve_mean}, {"p50", m.solve_p50}, {"p99", m.solve_p99}, {"max", m.solve_max}};
  j["iterations"] = {{"mean", m.iterations_mean}, {"max", m.iterations_max}};
  j["periods"] = m.periods;
  j["deadline_misses"] = m.deadline_misses;
  j["fallback_periods"] = m.fallback_periods;
  j["reverted_periods"] = m.reverted_periods;
  j["clipped_periods"] = m.clipped_periods;
  j["tube_exits"] = {{"total", m.tube_exits},
                     {"window_starts", m.window_starts},
                     {"per_disturbance_step", m.tube_exits_per_step},
                     {"max_distance_per_step", m.tube_ratio_max_per_step},
                     {"settle_s_per_step", m.tube_settle_s_per_step},
                     {"worst_state", m.tube_worst_state}};
  j["state_constraint_violations"] = m.state_constraint_violations;
  j["violation"] = {{"max_ratio", m.violation_max_ratio}, {"worst_state", m.violation_worst_state}};
  nlohmann::json peak = nlohmann::json::object();
  for (std::size_t i = 0; i < m.box_peak_ratio.size(); ++i) peak[name(m.box_names, i, "state")] = m.box_peak_ratio[i];
  j["box_peak_ratio"] = peak;
  j["softened"] = {{"periods", m.softened_periods}, {"slack_max", m.slack_max}, {"worst_state", m.slack_worst_state}};
  j["yaw_into_force"] = {{"offset_max", m.yaw_offset_max}, {"periods_turned", m.yaw_governed_periods}};
  j["estimator"] = m.estimator;
  if (!m.join_offset.empty()) j["reference_join"] = {{"offset", m.join_offset}, {"duration_s", m.join_duration}};
  j["observer"] = {{"filtered_periods", m.filtered_periods}, {"switches", m.observer_switches}, {"noise_level_max", m.noise_level_max},
                   {"filter_louder_periods", m.filter_louder_periods}, {"filter_noise_scale_max", m.filter_noise_scale_max},
                   {"gated_samples", m.gated_samples},
                   {"step_detections", m.step_detections},
                   {"step_lift_reopenings", m.step_lift_reopenings},
                   {"step_actuator_corrections", m.step_actuator_corrections},
                   {"step_late_kept", m.step_late_kept}};
  j["d_hat_final"] = m.d_hat_final;
  j["solver"] = m.solver;
  j["plant"] = m.plant;
  j["scenario"] = m.scenario;
  j["noisy_sensors"] = m.noisy;
  j["tube_law"] = m.offset_free ? "offset-free" : "mayne";
  j["diverged"] = m.diverged;
  return j.dump(2);
}

}  // namespace tmpc
