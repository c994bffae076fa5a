// Closed-loop mission on a virtual clock.
#include "tmpc/metrics/mission.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/tracking_error.hpp"
#include "tmpc/runtime/tube_controller.hpp"
#include "tmpc/sim/plant.hpp"

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

MissionMetrics run_mission(const ControllerArtifact& a, const MissionOptions& o) {
  Config cfg = load_config_from_string(a.config_text, "artifact");
  if (o.seed >= 0) cfg.perturbation.seed = static_cast<unsigned>(o.seed);
  const TiltrotorModel model(cfg.vehicle);
  const HelixTrajectory traj(cfg.reference, model);
  auto plant = make_plant(o.plant, cfg, o.disturbance, o.run);
  SolverOptions so;
  so.eps_abs = so.eps_rel = cfg.solver.admm_epsilon;
  so.eta = cfg.solver.admm_eta;
  TubeControllerOptions to = tube_law_options(cfg, o.tube_law, o.observer_gain);
  to.reinitialize_nominal = o.reinitialize_nominal;
  std::unique_ptr<QpSolver> solver = make_controller_solver(o.solver, a, so, o.explicit_law, to.offset_free);
  if (o.record_qps != nullptr) solver = std::make_unique<RecordingSolver>(std::move(solver), o.record_qps);
  TubeController ctrl(a, std::move(solver), to);

  MissionMetrics m;
  m.solver = o.solver;
  m.plant = o.plant;
  m.offset_free = to.offset_free;
  const double T = a.sample_time;
  const long K = std::lround(o.duration / T);
  const ReferencePoint r0 = traj.at(0.0);
  State20 x0;
  x0 << r0.q, r0.qd;  // start on the reference (E8)
  plant->reset(x0, 0.0);
  TrackingError err;
  ctrl.reset(err.value());
  Eigen::Vector4d u_prev = Eigen::Vector4d::Zero();
  std::vector<double> solve;
  solve.reserve(static_cast<std::size_t>(K));
  std::array<double, 10> sq{};
  std::vector<double> step_times;
  for (const DisturbanceStep& s : cfg.disturbances) step_times.push_back(s.time);
  m.tube_exits_per_step.assign(o.disturbance ? step_times.size() + 1 : 1, 0);
  m.tube_ratio_max_per_step.assign(m.tube_exits_per_step.size(), 0.0);
  m.tube_settle_s_per_step.assign(m.tube_exits_per_step.size(), 0.0);
  std::vector<long> worst_count(static_cast<std::size_t>(a.n), 0);
  std::ofstream csv;
  if (!o.telemetry_csv.empty()) {
    csv.open(o.telemetry_csv);
    csv << "t";
    for (const char* n : kCoordNames) csv << ",e_" << n;
    for (const char* n : kCoordNames) csv << ",r_" << n;
    csv << ",u_f_r,u_f_l,u_tau_r,u_tau_l,ubar_f_r,ubar_f_l,ubar_tau_r,ubar_tau_l,status,iterations,solve_us,fallback,"
           "clipped,in_tube,in_state_box,tube_ratio,tube_worst,dhat_x,dhat_y,dhat_z\n";
  }
  const double box_limit = 10.0;
  for (long k = 0; k < K; ++k) {
    const double t = static_cast<double>(k) * T;
    const ReferencePoint r = traj.at(t);
    const State20& x = plant->state();
    const Eigen::VectorXd& xt = err.update(x, r);
    if (!xt.allFinite() || (a.N_x.cwiseProduct(xt).cwiseAbs().array() > box_limit).any()) {
      m.diverged = true;
      break;
    }
    const Eigen::Vector4d ur = feedforward(model, r);
    const ControlStep& s = ctrl.step(xt, ur);
    plant->advance(s.u, T);
    err.integrate(T);
    ++m.periods;
    for (int i = 0; i < 10; ++i) sq[static_cast<std::size_t>(i)] += xt(i) * xt(i);
    for (int i = 0; i < 3; ++i) m.max_abs_error[static_cast<std::size_t>(i)] = std::max(m.max_abs_error[static_cast<std::size_t>(i)], std::abs(xt(i)));
    if (k > 0) {
      for (int i = 0; i < 4; ++i) m.tcv[static_cast<std::size_t>(i)] += std::abs(s.u(i) - u_prev(i));
    }
    u_prev = s.u;
    solve.push_back(s.solve_us);
    m.iterations_mean += s.iterations;
    m.iterations_max = std::max(m.iterations_max, s.iterations);
    m.fallback_periods += s.fallback;
    m.clipped_periods += s.clipped;
    m.state_constraint_violations += !s.in_state_box;
    for (int i = 0; i < 3; ++i) m.d_hat_final[static_cast<std::size_t>(i)] = s.d_hat(i);
    std::size_t w = 0;  // the disturbance window of this period
    if (o.disturbance) {
      while (w < step_times.size() && t >= step_times[w]) ++w;
    }
    m.tube_ratio_max_per_step[w] = std::max(m.tube_ratio_max_per_step[w], s.tube_ratio);
    if (!s.in_tube) {
      ++m.tube_exits;
      ++m.tube_exits_per_step[w];
      m.tube_settle_s_per_step[w] = t + T - (w == 0 ? 0.0 : step_times[w - 1]);
      ++worst_count[static_cast<std::size_t>(s.tube_worst)];
    }
    if (csv) {
      csv << t;
      for (int i = 0; i < 10; ++i) csv << "," << xt(i);
      for (int i = 0; i < 10; ++i) csv << "," << r.q(i);
      for (int i = 0; i < 4; ++i) csv << "," << s.u(i);
      for (int i = 0; i < 4; ++i) csv << "," << s.u_bar(i);
      csv << "," << to_string(s.status) << "," << s.iterations << "," << s.solve_us << "," << s.fallback << ","
          << s.clipped << "," << s.in_tube << "," << s.in_state_box << "," << s.tube_ratio << ","
          << s.tube_worst << "," << s.d_hat(0) << "," << s.d_hat(1) << "," << s.d_hat(2) << "\n";
    }
  }
  const auto most = std::max_element(worst_count.begin(), worst_count.end());
  if (m.tube_exits > 0) m.tube_worst_state = error_state_name(static_cast<int>(most - worst_count.begin()));
  const double n = std::max<double>(1.0, static_cast<double>(m.periods));
  for (int i = 0; i < 10; ++i) m.rmse[static_cast<std::size_t>(i)] = std::sqrt(sq[static_cast<std::size_t>(i)] / n);
  m.iterations_mean /= n;
  if (!solve.empty()) {
    std::sort(solve.begin(), solve.end());
    auto pct = [&](double p) { return solve[std::min(solve.size() - 1, static_cast<std::size_t>(p * solve.size()))]; };
    m.solve_min = solve.front();
    m.solve_max = solve.back();
    m.solve_p50 = pct(0.5);
    m.solve_p99 = pct(0.99);
    double sum = 0;
    for (double v : solve) sum += v;
    m.solve_mean = sum / static_cast<double>(solve.size());
  }
  return m;
}

std::string metrics_json(const MissionMetrics& m) {
  nlohmann::json j;
  nlohmann::json rmse;
  for (int i = 0; i < 10; ++i) rmse[kCoordNames[static_cast<std::size_t>(i)]] = m.rmse[static_cast<std::size_t>(i)];
  j["rmse"] = rmse;
  j["tcv"] = {{"f_r", m.tcv[0]}, {"f_l", m.tcv[1]}, {"tau_r", m.tcv[2]}, {"tau_l", m.tcv[3]}};
  j["solve_us"] = {{"min", m.solve_min}, {"mean", m.solve_mean}, {"p50", m.solve_p50}, {"p99", m.solve_p99}, {"max", m.solve_max}};
  j["iterations"] = {{"mean", m.iterations_mean}, {"max", m.iterations_max}};
  j["periods"] = m.periods;
  j["deadline_misses"] = m.deadline_misses;
  j["fallback_periods"] = m.fallback_periods;
  j["clipped_periods"] = m.clipped_periods;
  j["tube_exits"] = {{"total", m.tube_exits},
                     {"per_disturbance_step", m.tube_exits_per_step},
                     {"max_distance_per_step", m.tube_ratio_max_per_step},
                     {"settle_s_per_step", m.tube_settle_s_per_step},
                     {"worst_state", m.tube_worst_state}};
  j["state_constraint_violations"] = m.state_constraint_violations;
  j["max_abs_error"] = {{"x", m.max_abs_error[0]}, {"y", m.max_abs_error[1]}, {"z", m.max_abs_error[2]}};
  j["solver"] = m.solver;
  j["plant"] = m.plant;
  j["tube_law"] = m.offset_free ? "offset-free" : "mayne";
  j["diverged"] = m.diverged;
  return j.dump(2);
}

}  // namespace tmpc
