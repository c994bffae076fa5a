// What a controller artifact must mean before anything runs (artifact.hpp,
// check_artifact()): the record container proved the bytes are the ones written;
// these checks prove the records are a controller this build can fly.
#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/error_model.hpp"
#include "tmpc/model/state_layout.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {

namespace {

class Checker {
 public:
  explicit Checker(const std::string& source) : source_(source) {}
  [[noreturn]] void fail(const std::string& record, const std::string& what) const {
    throw ArtifactError(source_ + ": record '" + record + "': " + what);
  }
  static std::string num(double v) {
    std::ostringstream os;
    os.precision(6);
    os << v;
    return os.str();
  }
  void positive(const std::string& record, const Eigen::VectorXd& v) const {
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      if (!(v(i) > 0.0)) fail(record, "entry " + std::to_string(i) + " is " + num(v(i)) + ", a scaling must be positive");
    }
  }
  void box(const std::string& record, const Box& b) const {
    const int e = b.first_empty_dimension();
    if (e >= 0) {
      fail(record + "_lo", "the set is empty in dimension " + std::to_string(e) + " (lo " + num(b.lo(e)) + " > hi " +
                               num(b.hi(e)) + ")");
    }
  }
  void inside(const std::string& record, const Box& inner, const Box& outer, const std::string& outer_name) const {
    for (int i = 0; i < inner.dim(); ++i) {
      if (inner.lo(i) < outer.lo(i) - 1e-12 || inner.hi(i) > outer.hi(i) + 1e-12) {
        fail(record + "_lo", "dimension " + std::to_string(i) + " [" + num(inner.lo(i)) + ", " + num(inner.hi(i)) +
                                 "] is not inside " + outer_name + " [" + num(outer.lo(i)) + ", " + num(outer.hi(i)) +
                                 "]: a tightened set lies inside its constraint set");
      }
    }
  }
  /// `kind` names what the matrix is ("a cost weight", "a covariance"); `scale_floor`
  /// the smallest scale the tolerances are relative to (covariances can be tiny).
  void symmetric_psd(const std::string& record, const Eigen::MatrixXd& m, bool definite,
                     const std::string& kind = "a cost weight", double scale_floor = 1.0) const {
    if (!m.allFinite()) fail(record, "has a non-finite entry");
    const double scale = std::max(scale_floor, m.cwiseAbs().maxCoeff());
    if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) fail(record, "is not symmetric");
    const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (m + m.transpose())).eigenvalues().minCoeff();
    if (definite ? !(lmin > 0.0) : lmin < -1e-9 * scale) {
      fail(record, std::string("smallest eigenvalue ") + num(lmin) + ": " + kind + " must be positive " +
                       (definite ? "definite" : "semidefinite"));
    }
  }
  void stabilizing(const std::string& record, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                   const Eigen::MatrixXd& K, const std::string& model) const {
    const double rho = spectral_radius(A + B * K);
    if (!(rho < 1.0)) {
      fail(record, "does not stabilize the " + model + " (spectral radius of A + B K = " + num(rho) + ", must be < 1)");
    }
  }
  void near(const std::string& record, double stored, double expected, double tol, const std::string& why) const {
    if (!(std::abs(stored - expected) <= tol * std::max(1.0, std::abs(expected)))) {
      fail(record, "is " + num(stored) + ", the embedded configuration gives " + num(expected) + " (" + why + ")");
    }
  }

 private:
  const std::string& source_;
};

/// The filter's covariances (artifact.hpp estimator_P, estimator_Q): Q a covariance, P
/// the stabilizing solution of the filter DARE of (A_a, C, Q, R) and L its gain, so the
/// start's Riccati recursion (estimator.hpp start_gains()) ends at the gain flown.
void check_filter_covariances(const Checker& c, const ControllerArtifact& a) {
  const KalmanDesign k = kalman_model(a);
  const Eigen::Index na = k.A_a.rows();
  c.symmetric_psd("estimator_Q", k.Q, false, "a covariance", 1e-300);
  c.symmetric_psd("estimator_P", k.P, false, "a covariance", 1e-300);
  const Eigen::MatrixXd S = k.C * k.P * k.C.transpose() + k.R;
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) c.fail("estimator_P", "C P C' + R is not positive definite");
  const Eigen::MatrixXd L = llt.solve(k.C * k.P).transpose();
  const double gain_gap = (L - k.L).cwiseAbs().maxCoeff() / std::max(1e-300, k.L.cwiseAbs().maxCoeff());
  if (!(gain_gap <= 1e-6)) {
    c.fail("estimator_P", "its gain P C' (C P C' + R)^-1 differs from estimator_L by " + Checker::num(gain_gap) +
                              " (relative): the covariance is not the filter's");
  }
  const Eigen::MatrixXd next = k.A_a * (Eigen::MatrixXd::Identity(na, na) - L * k.C) * k.P * k.A_a.transpose() + k.Q;
  const double dare_gap = (next - k.P).cwiseAbs().maxCoeff() / std::max(1e-300, k.P.cwiseAbs().maxCoeff());
  if (!(dare_gap <= 1e-6)) {
    c.fail("estimator_P", "is not a fixed point of the filter's Riccati equation (relative residual " +
                              Checker::num(dare_gap) + "): the covariance does not match estimator_Q");
  }
  const Eigen::Vector3d& s = a.estimator_start;
  if (!s.allFinite() || (s.array() < 0.0).any()) {
    c.fail("estimator_start", "is (" + Checker::num(s(0)) + ", " + Checker::num(s(1)) + ", " + Checker::num(s(2)) +
                                  "): standard deviations are finite and >= 0");
  }
}

/// The QP in a form the runtime builds (artifact.qp(offset_free, soft): controller_solver.cpp),
/// built as it will be: a record the builders refuse refuses the artifact here, with their message.
MpcQpData built_qp(const std::string& source, const ControllerArtifact& a, bool offset_free, bool soft) {
  try {
    return a.qp(offset_free, soft);
  } catch (const std::exception& e) {
    throw ArtifactError(source + ": the QP" + (offset_free ? " around the disturbance's steady state" : "") +
                        (soft ? " with soft constraints" : "") + " cannot be built from the records: " + e.what());
  }
}

void check_records(const ControllerArtifact& a, const std::string& source) {
  const Checker c(source);
  // Dimensions the runtime supports, and every record consistent with them.
  const bool tilt = a.model == ModelKind::Tiltrotor;
  if (a.n < 1 || a.n > kMaxStates) c.fail("n", "is " + std::to_string(a.n) + ", must be in [1, " + std::to_string(kMaxStates) + "]");
  if (a.m < 1 || a.m > kMaxInputs) c.fail("m", "is " + std::to_string(a.m) + ", must be in [1, " + std::to_string(kMaxInputs) + "]");
  if (tilt && (a.n != kNa || a.m != kNu || a.measured != kNx)) {
    c.fail("n", "is " + std::to_string(a.n) + " with " + std::to_string(a.measured) + " measured states and " +
                    std::to_string(a.m) + " inputs: the tiltrotor has " + std::to_string(kNa) + ", " +
                    std::to_string(kNx) + " and " + std::to_string(kNu));
  }
  if (tilt && a.D.cols() != kNd) c.fail("D", "has " + std::to_string(a.D.cols()) + " columns, the load force has " + std::to_string(kNd));
  if (static_cast<int>(a.kinds.size()) != a.n) c.fail("state_kinds", "has " + std::to_string(a.kinds.size()) + " entries for " + std::to_string(a.n) + " states");
  for (int i = 0; i < a.n; ++i) {
    const bool integral = a.kinds[static_cast<std::size_t>(i)] == StateKind::Integral;
    if (integral != (i >= a.measured)) {
      c.fail("state_kinds", "state " + std::to_string(i) + " (" + a.state_names[static_cast<std::size_t>(i)] + ") is " +
                                to_string(a.kinds[static_cast<std::size_t>(i)]) + ": integral states come after the " +
                                std::to_string(a.measured) + " measured ones, and only there");
    }
  }
  if (tilt && a.kinds != tiltrotor_state_kinds()) c.fail("state_kinds", "are not the tiltrotor's");
  if (a.N < 1 || a.N > kMaxHorizon) c.fail("N", "is " + std::to_string(a.N) + ", must be in [1, " + std::to_string(kMaxHorizon) + "]");
  if (a.M < 1 || a.M > a.N) c.fail("M", "is " + std::to_string(a.M) + ", must be in [1, N = " + std::to_string(a.N) + "]");
  if (!(a.sample_time >= 1e-5 && a.sample_time <= 1.0)) c.fail("sample_time", "is " + Checker::num(a.sample_time) + " s, must be in [1e-5, 1] s");
  if (!(a.substep > 0.0 && a.substep <= a.sample_time)) c.fail("substep", "is " + Checker::num(a.substep) + " s, must be in (0, sample_time]");
  if (a.A_vertices.size() > 64) c.fail("vertices", "is " + std::to_string(a.A_vertices.size()) + ", at most 64");
  c.positive("N_x", a.N_x);
  c.positive("N_u", a.N_u);
  // Limits: the feedforward range inside the actuator limits (room left for feedback).
  for (int i = 0; i < a.m; ++i) {
    if (!(a.input_max(i) > a.input_min(i))) c.fail("input_max", "entry " + std::to_string(i) + " is not above input_min");
    if (a.feedforward_min(i) > a.feedforward_max(i) || a.feedforward_min(i) < a.input_min(i) ||
        a.feedforward_max(i) > a.input_max(i)) {
      c.fail("feedforward_min", "entry " + std::to_string(i) + " [" + Checker::num(a.feedforward_min(i)) + ", " +
                                    Checker::num(a.feedforward_max(i)) + "] leaves the input limits [" +
                                    Checker::num(a.input_min(i)) + ", " + Checker::num(a.input_max(i)) + "]");
    }
  }
  if (tilt) {
    for (int i = 0; i < 3; ++i) {
      if (!(a.envelope.acceleration_max(i) >= a.envelope.acceleration_min(i))) c.fail("envelope_acceleration_max", "below the minimum on axis " + std::to_string(i));
    }
    if (!(a.envelope.speed_max >= 0.0) || !(a.envelope.yaw_tolerance >= 0.0)) c.fail("envelope_numbers", "negative speed or yaw tolerance");
    if (a.envelope.yaw_rate_max > 10.0) {  // (non-finite records are refused before)
      c.fail("envelope_numbers", "yaw rate bound " + Checker::num(a.envelope.yaw_rate_max) + " above 10 rad/s");
    }
  }
  if (!(a.solver.admm_epsilon > 0.0 && a.solver.admm_epsilon <= 1.0)) c.fail("solver", "epsilon " + Checker::num(a.solver.admm_epsilon) + " not in (0, 1]");
  if (!(a.solver.admm_eta > 0.0 && a.solver.admm_eta < 1.0)) c.fail("solver", "eta " + Checker::num(a.solver.admm_eta) + " not in (0, 1)");
  if (!(a.tube_law.observer_gain > 0.0 && a.tube_law.observer_gain <= 1.0)) c.fail("tube_law_observer_gain", "is " + Checker::num(a.tube_law.observer_gain) + ", must be in (0, 1]");
  if (!a.tube_law.revert_beyond_valid()) c.fail("tube_law_revert", "enter bound " + Checker::num(a.tube_law.revert_beyond) + " is neither 0 (off) nor above 1");
  if (a.tube_law.revert_beyond_valid() && !a.tube_law.revert_within_valid()) c.fail("tube_law_revert", "leave bound " + Checker::num(a.tube_law.revert_within) + " not in [1, the enter bound]");
  if (!(a.link.plant_hold_s >= 0.0) || !(a.link.time_tolerance > 0.0) || !(a.link.bound_time > 0.0)) c.fail("link_numbers", "a hold time, tolerance or bound is not positive");
  // Sets: non-empty, the tightened ones inside theirs, the tube and W of the right size.
  c.box("X", a.X);
  c.box("U", a.U);
  c.box("x_bar", a.x_bar);
  c.box("u_bar", a.u_bar);
  c.inside("x_bar", a.x_bar, a.X, "X");
  c.inside("u_bar", a.u_bar, a.U, "U");
  if (a.Z.order() < 1) c.fail("Z_G", "the tube has no generator");
  if (!(a.margin >= 1.0 - 1e-9)) c.fail("margin", "is " + Checker::num(a.margin) + ": the design's own W must fit (margin >= 1)");
  // The cost is convex and the laws stabilize.
  c.symmetric_psd("Sigma_rho", a.Sigma_rho, false);
  c.symmetric_psd("Sigma_lambda", a.Sigma_lambda, true);
  if (a.Sigma_delta.size() > 0) {
    if (a.Sigma_delta.rows() != a.m || a.Sigma_delta.cols() != a.m) c.fail("Sigma_delta", "is not m x m");
    c.symmetric_psd("Sigma_delta", a.Sigma_delta, false);
  }
  c.symmetric_psd("L", a.L, false);
  c.symmetric_psd("P_lqr", a.P_lqr, true);
  const MpcQpData qp = built_qp(source, a, false, false);
  if (Eigen::LLT<Eigen::MatrixXd>(qp.H).info() != Eigen::Success) {
    c.fail("Sigma_lambda", "the QP Hessian H = 2 (P'W_x P + W_u) is not positive definite: the cost is not strictly convex");
  }
  c.stabilizing("K", a.A, a.B, a.K, "nominal model");
  for (std::size_t i = 0; i < a.A_vertices.size(); ++i) {
    c.stabilizing("K", a.A_vertices[i], a.B, a.K, "LPV vertex " + std::to_string(i));
  }
  c.stabilizing("K_lqr", a.A, a.B, a.K_lqr, "nominal model (LQR fallback)");
  if (a.tube_law.offset_free) {
    try {
      a.disturbance_target();
    } catch (const std::exception& e) {
      c.fail("tube_law_offset_free", std::string("the offset-free law needs a steady state of every disturbance: ") + e.what());
    }
  }
  // State estimation: a filter whose error converges, and the soft constraints' penalty.
  if (a.estimator == "kalman") {
    if (!a.tube_law.offset_free) c.fail("estimator", "kalman estimates the offset-free law's disturbance: tube_law_offset_free must be 1");
    const Eigen::Index na = a.measured + a.D.cols() + a.estimator_E_c.cols();
    if (a.estimator_E_c.rows() != a.measured || a.estimator_L.rows() != na ||
        a.estimator_L.cols() != static_cast<Eigen::Index>(a.estimator_rows.size())) {
      c.fail("estimator_L", "is " + std::to_string(a.estimator_L.rows()) + "x" + std::to_string(a.estimator_L.cols()) +
                                ", expected " + std::to_string(na) + "x" + std::to_string(a.estimator_rows.size()));
    }
    for (std::size_t i = 0; i < a.estimator_rows.size(); ++i) {
      if ((i > 0 && a.estimator_rows[i] <= a.estimator_rows[i - 1]) || a.estimator_rows[i] >= a.measured) {
        c.fail("estimator_rows", "are not increasing indices of measured states");
      }
    }
    if (a.estimator_noise.size() != static_cast<Eigen::Index>(a.estimator_rows.size()) ||
        !(a.estimator_noise.array() > 0.0).all() || !a.estimator_noise.allFinite()) {
      c.fail("estimator_noise", "needs a positive finite standard deviation for each of the " +
                                    std::to_string(a.estimator_rows.size()) + " measured rows");
    }
    const Eigen::Vector3d& mo = a.estimator_monitor;
    if (!mo.allFinite() || mo(0) < 0.0 || mo(1) < mo(0) || !(mo(2) > 0.0 && mo(2) <= 60.0)) {
      c.fail("estimator_monitor", "is (" + Checker::num(mo(0)) + ", " + Checker::num(mo(1)) + ", " + Checker::num(mo(2)) +
                                      "): expected 0 <= residual_below <= filter_above and a window in (0, 60] s");
    }
    const double rho = spectral_radius(estimation_error_map(a));
    if (!(rho < 1.0)) c.fail("estimator_L", "the estimation error does not converge (spectral radius of (I - L C) A_a = " + Checker::num(rho) + ")");
    check_filter_covariances(c, a);
  }
  if (!(a.noise_margin >= 0.0) || !std::isfinite(a.noise_margin)) c.fail("noise_margin", "is " + Checker::num(a.noise_margin));
  if (!(a.estimation_error_radius.array() >= 0.0).all()) c.fail("estimation_error_radius", "has a negative half-width");
  if (!(a.soft_penalty >= 0.0) || !std::isfinite(a.soft_penalty)) c.fail("soft_penalty", "is " + Checker::num(a.soft_penalty) + ", must be >= 0");
  if (!(a.certificate_d_max.array() >= 0.0).all() || !a.certificate_d_max.allFinite()) c.fail("certificate_d_max", "has a negative or non-finite entry");
  if (!(a.certificate_c_max.array() >= 0.0).all() || !a.certificate_c_max.allFinite()) c.fail("certificate_c_max", "has a negative or non-finite entry");
  if (a.soft_constraints && !(a.soft_penalty > 0.0)) {
    c.fail("soft_penalty", "is 0 with soft constraints on: calibrate it (tmpc design runs calibrate_soft_penalty) or configure soft_constraints.penalty");
  }
  if (a.tube_law.offset_free) built_qp(source, a, true, false);
  if (a.soft_constraints) built_qp(source, a, a.tube_law.offset_free, true);
  // The embedded configuration: valid, and the records are the design it describes.
  Config cfg;
  try {
    cfg = load_config_from_string(a.config_text, source + " (embedded configuration)");
  } catch (const ConfigError& e) {
    c.fail("config", std::string("the embedded configuration is invalid: ") + e.what());
  }
  if (cfg.model != a.model) c.fail("model", "differs from the embedded configuration's model");
  if (cfg.states() != a.n || cfg.inputs() != a.m || cfg.measured() != a.measured || cfg.integrated() != a.integrated) {
    c.fail("n", "the embedded configuration has " + std::to_string(cfg.states()) + " states (" + std::to_string(cfg.measured()) +
                    " measured) and " + std::to_string(cfg.inputs()) + " inputs");
  }
  if (cfg.state_names() != a.state_names) c.fail("state_names", "differ from the embedded configuration's");
  c.near("sample_time", a.sample_time, cfg.sample_time, 1e-12, "sample_time");
  c.near("substep", a.substep, cfg.simulation.substep, 1e-12, "simulation.substep");
  if (a.model == ModelKind::Tiltrotor) {  // an any-yaw record on a fixed-yaw design would fly yaws it was not made for
    c.near("envelope_numbers", a.envelope.yaw_rate_max, cfg.envelope.yaw_rate_max, 1e-12, "envelope.yaw_rate_max");
  }
  if (a.N != cfg.synthesis.horizon) c.fail("N", "is " + std::to_string(a.N) + ", the embedded configuration's synthesis.horizon is " + std::to_string(cfg.synthesis.horizon));
  if (a.M != cfg.synthesis.control_horizon) c.fail("M", "is " + std::to_string(a.M) + ", the embedded configuration's synthesis.control_horizon is " + std::to_string(cfg.synthesis.control_horizon));
  if (a.tube_gain != cfg.synthesis.tube_gain) c.fail("tube_gain", "is '" + a.tube_gain + "', the embedded configuration's synthesis.tube_gain is '" + cfg.synthesis.tube_gain + "'");
  if (a.rpi_variant != cfg.synthesis.rpi_variant) c.fail("rpi_variant", "is '" + a.rpi_variant + "', the embedded configuration's synthesis.rpi.variant is '" + cfg.synthesis.rpi_variant + "'");
  if (a.terminal_cost != cfg.synthesis.terminal_cost) c.fail("terminal_cost", "is '" + a.terminal_cost + "', the embedded configuration's synthesis.terminal_cost is '" + cfg.synthesis.terminal_cost + "'");
  if (a.tube_law.offset_free != cfg.tube_law.offset_free) c.fail("tube_law_offset_free", "differs from the embedded configuration's tube_law.offset_free");
  c.near("tube_law_observer_gain", a.tube_law.observer_gain, cfg.tube_law.observer_gain, 1e-12, "tube_law.observer_gain");
  c.near("tube_law_revert", a.tube_law.revert_beyond, cfg.tube_law.revert_beyond, 1e-12, "tube_law.revert_beyond");
  c.near("tube_law_revert", a.tube_law.revert_within, cfg.tube_law.revert_within, 1e-12, "tube_law.revert_within");
  c.near("solver", a.solver.admm_epsilon, cfg.solver.admm_epsilon, 1e-12, "solver.admm_epsilon");
  if (a.link.watchdog_periods != cfg.link.watchdog_periods) c.fail("link_watchdog_periods", "differs from the embedded configuration's link.watchdog_periods");
  if (a.estimator != cfg.estimation.observer) c.fail("estimator", "is '" + a.estimator + "', the embedded configuration's estimation.observer is '" + cfg.estimation.observer + "'");
  if (a.estimator == "kalman") {
    c.near("estimator_monitor", a.estimator_monitor(0), cfg.estimation.monitor_residual_below, 1e-12, "estimation.noise_monitor.residual_below");
    c.near("estimator_monitor", a.estimator_monitor(1), cfg.estimation.monitor_filter_above, 1e-12, "estimation.noise_monitor.filter_above");
    c.near("estimator_monitor", a.estimator_monitor(2), cfg.estimation.monitor_window_s, 1e-12, "estimation.noise_monitor.window");
    c.near("estimator_start", a.estimator_start(0), cfg.estimation.start_force, 1e-12, "estimation.start_prior.force");
    c.near("estimator_start", a.estimator_start(1), cfg.estimation.start_residual, 1e-12, "estimation.start_prior.residual");
    c.near("estimator_start", a.estimator_start(2), cfg.estimation.start_state, 1e-12, "estimation.start_prior.state");
  }
  if (a.soft_constraints != cfg.soft_constraints.enabled) c.fail("soft_constraints", "differs from the embedded configuration's soft_constraints.enabled");
  if (cfg.estimation.output_feedback_tube && !(a.noise_margin >= 1.0 - 1e-9)) {
    c.fail("noise_margin", "is " + Checker::num(a.noise_margin) + ": the configured noise must fit the output-feedback tube (>= 1)");
  }
  for (int i = 0; i < a.n; ++i) {
    c.near("N_x", a.N_x(i), 1.0 / cfg.state_error_max(i), 1e-12, "1 / constraints.state_error_max[" + std::to_string(i) + "]");
  }
  for (int i = 0; i < a.m; ++i) {
    c.near("N_u", a.N_u(i), 2.0 / (cfg.input_max(i) - cfg.input_min(i)), 1e-12,
           "2 / (input_max - input_min)[" + std::to_string(i) + "]");
    c.near("input_min", a.input_min(i), cfg.input_min(i), 1e-12, "constraints.input_min[" + std::to_string(i) + "]");
    c.near("input_max", a.input_max(i), cfg.input_max(i), 1e-12, "constraints.input_max[" + std::to_string(i) + "]");
    const double rate = a.Sigma_delta.size() > 0 ? a.Sigma_delta(i, i) : 0.0;
    c.near("Sigma_delta", rate, cfg.input_rate_weights(i) / (a.N_u(i) * a.N_u(i)), 1e-9,
           "weights.input_rate[" + std::to_string(i) + "] / N_u^2");
  }
  if (!tilt) {
    if (a.linear_A != cfg.linear.A || a.linear_B != cfg.linear.B || a.linear_D != cfg.linear.D) {
      c.fail("linear_A", "the linear model differs from the embedded configuration's");
    }
    return;
  }
  // The vehicle: the records' parameters are the embedded configuration's, and their
  // hover equilibrium is the stored one (a model edited after the design, e.g. a mass).
  const VehicleParams& v = a.vehicle;
  const VehicleParams& w = cfg.vehicle;
  const double scalars[9] = {v.gravity, v.load_mass, v.rod_length, v.body_mass, v.rotor_mass, v.dihedral, v.drag_torque_ratio, v.spin_right, v.spin_left};
  const double expected[9] = {w.gravity, w.load_mass, w.rod_length, w.body_mass, w.rotor_mass, w.dihedral, w.drag_torque_ratio, w.spin_right, w.spin_left};
  for (int i = 0; i < 9; ++i) c.near("vehicle_scalars", scalars[i], expected[i], 1e-12, "the vehicle section, entry " + std::to_string(i));
  if (v.load_inertia != w.load_inertia || v.body_inertia != w.body_inertia || v.rotor_inertia != w.rotor_inertia ||
      v.d_a1b != w.d_a1b || v.d_b1 != w.d_b1 || v.rotor_com != w.rotor_com || v.d_b_right != w.d_b_right ||
      v.d_b_left != w.d_b_left || v.friction != w.friction || v.rotor_inertia_reference != w.rotor_inertia_reference) {
    c.fail("vehicle_vectors", "the vehicle's inertias or geometry differ from the embedded configuration's");
  }
  Equilibrium eq;
  try {
    eq = solve_hover_equilibrium(TiltrotorModel(a.vehicle), a.envelope.yaw);
  } catch (const std::exception& e) {
    c.fail("vehicle_scalars", std::string("the vehicle has no hover equilibrium: ") + e.what());
  }
  for (int i = 0; i < 4; ++i) c.near("u_eq", a.u_eq(i), eq.u(i), 1e-6, "the hover input of the embedded vehicle");
  for (int i = 0; i < 4; ++i) c.near("angles_eq", a.angles_eq(i), eq.angles(i), 1e-6, "the hover angles of the embedded vehicle");
}

}  // namespace

void check_artifact(const ControllerArtifact& a, const std::string& source) {
  // Every refusal is an ArtifactError naming the file: a check's own computation that
  // throws (an Eigen size, a builder's precondition) on records no check foresaw refuses
  // the artifact too, instead of escaping the loader as another exception.
  try {
    check_records(a, source);
  } catch (const ArtifactError&) {
    throw;
  } catch (const std::exception& e) {
    throw ArtifactError(source + ": the records could not be checked: " + e.what());
  }
}

}  // namespace tmpc
