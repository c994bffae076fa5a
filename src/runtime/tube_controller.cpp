#include "tmpc/runtime/tube_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/QR>

namespace tmpc {

void TubeControllerOptions::validate() const {
  if (!(observer_gain > 0.0 && observer_gain <= 1.0)) {
    throw std::invalid_argument("tube controller: observer_gain must be in (0, 1], got " + std::to_string(observer_gain));
  }
  if (observer != "residual" && observer != "kalman" && observer != "switched") {
    throw std::invalid_argument("tube controller: observer must be residual, kalman or switched, got '" + observer + "'");
  }
  if (!TubeLawSettings::revert_beyond_valid(revert_beyond)) {
    throw std::invalid_argument("tube controller: revert_beyond must be 0 (off) or above 1 (times the state bounds), got " +
                                std::to_string(revert_beyond));
  }
  if (!TubeLawSettings::revert_within_valid(revert_beyond, revert_within)) {
    throw std::invalid_argument("tube controller: revert_within must be in [1, revert_beyond = " + std::to_string(revert_beyond) +
                                "], got " + std::to_string(revert_within));
  }
}

TubeControllerOptions tube_law_options(const ControllerArtifact& a, const std::string& law, double observer_gain,
                                       const std::string& observer) {
  TubeControllerOptions o;
  o.offset_free = a.tube_law.offset_free;
  o.observer_gain = a.tube_law.observer_gain;
  o.revert_beyond = a.tube_law.revert_beyond;
  o.revert_within = a.tube_law.revert_within;
  o.observer = a.switched_observer() ? "switched" : a.estimator;
  if (observer == "residual" || observer == "kalman" || observer == "switched") {
    o.observer = observer;
  } else if (!observer.empty()) {
    throw std::invalid_argument("observer '" + observer + "' (expected residual, kalman or switched)");
  }
  if (o.observer != "residual" && a.estimator != "kalman") {
    throw std::invalid_argument("observer " + o.observer + ": the artifact has no Kalman filter (its config's estimation.observer is " +
                                a.estimator + ")");
  }
  if (o.observer == "switched" && !a.switched_observer()) {
    throw std::invalid_argument("observer switched: the artifact has no noise monitor (its config's estimation.noise_monitor)");
  }
  if (law == "mayne") {
    o.offset_free = false;
  } else if (law == "offset-free") {
    o.offset_free = true;
  } else if (!law.empty()) {
    throw std::invalid_argument("tube law '" + law + "' (expected mayne or offset-free)");
  }
  if (observer_gain > 0.0) o.observer_gain = observer_gain;
  o.validate();
  return o;
}

TubeController::TubeController(const ControllerArtifact& a, std::unique_ptr<QpSolver> solver, TubeControllerOptions opt)
    : a_(a), solver_(std::move(solver)), opt_(opt) {
  opt_.validate();
  const int n = a.n, m = a.m, nd = static_cast<int>(a.D.cols());
  x_bar_ = x_n_ = e_ = dev_ = next_ = x_s_ = c_hat_ = x_prev_ = resid_ = Eigen::VectorXd::Zero(n);
  u_s_ = u_prev_n_ = u_n_ = ub_ = u_raw_ = v_prev_ = Eigen::VectorXd::Zero(m);
  rate_ = a.rate_weighted();
  d_hat_ = d_raw_ = d_res_ = d_kf_ = Eigen::VectorXd::Zero(nd);
  c_res_ = c_kf_ = y_ = Eigen::VectorXd::Zero(n);
  z_half_ = a.Z.radius();
  out_.x_bar = Eigen::VectorXd::Zero(n);
  out_.u = out_.u_bar = Eigen::VectorXd::Zero(m);
  out_.d_hat = Eigen::VectorXd::Zero(nd);
  if (opt_.offset_free) {
    const DisturbanceTarget t = a.disturbance_target();
    Tx_ = t.Tx;
    Tu_ = t.Tu;
    // The measured velocities observe the disturbance (tiltrotor: the load's x, y, z
    // accelerations): the tilt and swing rows of D are dominated by servo and pendulum
    // mismatch, which biased the estimate by 0.1 to 0.3 N in the helix mission.
    std::vector<int> rows = a.velocity_rows();
    if (rows.empty()) {
      for (int i = 0; i < a.measured; ++i) rows.push_back(i);
    }
    D_pinv_ = disturbance_pseudo_inverse(a.D, rows);
    theta_ = Eigen::VectorXd::Zero(2 * n + nd + (rate_ ? m : 0));
    residual_ = opt_.observer != "kalman";
    if (opt_.observer != "residual") {
      if (a.estimator != "kalman") throw std::invalid_argument("tube controller: observer " + opt_.observer + ", but the artifact has no Kalman filter");
      const KalmanDesign k = kalman_model(a);
      kalman_ = true;
      A_a_ = k.A_a;
      B_a_ = k.B_a;
      L_kf_ = a.estimator_L;
      if (a.filter_start_scheduled()) {
        start_ = shared_start_schedule(
            k, start_covariance(k, a.D.cols(), a.estimator_start(0), a.estimator_start(1), a.estimator_start(2)));
      }
      E_c_ = a.estimator_E_c;
      rows_ = a.estimator_rows;
      prior_refuted_.assign(static_cast<std::size_t>(n), 0);
      xi_ = xi_pred_ = Eigen::VectorXd::Zero(k.A_a.rows());
      x_hat_ = Eigen::VectorXd::Zero(n);
      innov_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows_.size()));
      innov_sd_ = innovation_sd(k);
      gate_run_.assign(rows_.size(), 0);
      gate_prev_innov_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows_.size()));
      step_sum_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows_.size()));
      step_armed_.assign(rows_.size(), 1);
      step_pending_.assign(rows_.size(), 0);
      for (std::size_t j = 0; j < rows_.size(); ++j) {
        const StateGroup g = group_of(a.kinds[static_cast<std::size_t>(rows_[j])]);
        if (g == StateGroup::Position || g == StateGroup::Angle) gated_rows_.push_back(j);
      }
    }
    if (opt_.observer == "switched") {
      if (!a.switched_observer()) throw std::invalid_argument("tube controller: observer switched, but the artifact has no noise monitor");
      NoiseMonitorSettings s;
      s.residual_below = a.estimator_monitor(0);
      s.filter_above = a.estimator_monitor(1);
      s.window_s = a.estimator_monitor(2);
      monitor_ = std::make_unique<NoiseMonitor>(a.A, a.estimator_rows, a.estimator_noise, a.kinds, a.sample_time, s);
      if (opt_.adaptive_filter_gain) schedule_ = std::make_unique<FilterGainSchedule>(kalman_model(a));
    } else if (opt_.observer == "kalman" && opt_.adaptive_filter_gain) {
      // The filter alone: the monitor only reads the noise level (it never hands over to
      // the residual observer: residual_below 0), for the gain schedule.
      NoiseMonitorSettings s;
      s.window_s = a.estimator_monitor(2);
      monitor_ = std::make_unique<NoiseMonitor>(a.A, a.estimator_rows, a.estimator_noise, a.kinds, a.sample_time, s);
      schedule_ = std::make_unique<FilterGainSchedule>(kalman_model(a));
    }
    if (kalman_ && monitor_ && opt_.step_detection) {  // steps are read only with a monitor
      // Per noise scale of the gain schedule up to kStepScaleMax (the design's alone
      // without one): the residuals unknown; the force's block kept, or with
      // step_reopens_lift the components whose target moves no state (header) unknown;
      // the states as at the start (0.5 of their noise where the artifact has none).
      const double state = a.estimator_start(2) > 0.0 ? a.estimator_start(2) : 0.5;
      std::vector<Eigen::Index> forces;  // their places in xi = (x, d, c)
      for (Eigen::Index j = 0; opt_.step_reopens_lift && j < Tx_.cols(); ++j) {
        if (kReopenForceStd * Tx_.col(j).cwiseAbs().maxCoeff() > kReopenTargetShift) continue;
        reopened_forces_.push_back(j);
        forces.push_back(a.measured + j);
      }
      // The step's classification (header): the columns of a step in every force and the
      // residuals, and in the re-opened forces and the residuals.
      const Eigen::Index nd = a.D.cols(), nx = A_a_.rows();
      std::vector<Eigen::Index> all, lift = forces;
      for (Eigen::Index j = 0; j < nd; ++j) all.push_back(a.measured + j);
      for (Eigen::Index j = a.measured + nd; j < nx; ++j) {
        all.push_back(j);
        lift.push_back(j);
      }
      const KalmanDesign design = kalman_model(a);
      if (opt_.step_corrects_input && !forces.empty()) {
        // The actuators' steps as disturbance steps (header): v_j with [D E_c] v_j = B_j
        // in least squares, kept where that matches B_j within kInputMatch.
        const Eigen::Index p = a.measured;
        const Eigen::MatrixXd W = design.A_a.block(0, p, p, nx - p);
        const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(W);
        std::vector<Eigen::VectorXd> cols;
        std::vector<double> prior;
        for (Eigen::Index j = 0; j < design.B_a.cols(); ++j) {
          const Eigen::VectorXd b = design.B_a.col(j).head(p);
          const Eigen::VectorXd v = cod.solve(b);
          const double sd = kInputStepStd * std::max(std::abs(a.input_min(j)), std::abs(a.input_max(j))) * a.N_u(j);
          if (b.norm() > 0.0 && (W * v - b).norm() <= kInputMatch * b.norm() && sd > 0.0 && std::isfinite(sd)) {
            cols.push_back(Eigen::VectorXd::Zero(nx));
            cols.back().tail(nx - p) = v;
            step_inputs_.push_back(static_cast<int>(j));
            prior.push_back(sd);
          }
        }
        input_steps_ = Eigen::MatrixXd::Zero(nx, static_cast<Eigen::Index>(cols.size()));
        input_prior_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(cols.size()));
        for (std::size_t i = 0; i < cols.size(); ++i) {
          input_steps_.col(static_cast<Eigen::Index>(i)) = cols[i];
          input_prior_(static_cast<Eigen::Index>(i)) = prior[i];
        }
      }
      const std::vector<double>& scales = FilterGainSchedule::scales();
      for (std::size_t i = 0; i < (schedule_ ? scales.size() : 1) && scales[i] <= kStepScaleMax; ++i) {
        const KalmanDesign& ks = schedule_ ? schedule_->design(i) : design;
        const Eigen::MatrixXd P0 = start_covariance(ks, nd, 0.0, kReopenResidualStd, state);
        reopen_.push_back(shared_start_schedule(ks, P0));
        if (forces.empty()) continue;
        Eigen::MatrixXd P0_lift = P0;
        open_states(P0_lift, forces, kReopenForceStd);
        reopen_lift_.push_back(shared_start_schedule(ks, P0_lift));
        const Eigen::VectorXd sd = innovation_sd(ks);
        sig_all_.emplace_back(ks.A_a, ks.C, ks.L, sd, all, kStepWindow);
        sig_lift_.emplace_back(ks.A_a, ks.C, ks.L, sd, lift, kStepWindow);
        if (!step_inputs_.empty()) {
          sig_input_.push_back(
              StepSignature::along(ks.A_a, ks.C, ks.L, sd, input_steps_, kStepWindow, input_prior_, kInputDetermined));
        }
      }
      if (!forces.empty()) {
        step_window_ = InnovationWindow(static_cast<Eigen::Index>(rows_.size()), kStepWindow);
        step_z_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows_.size()));
        lift_threshold_ = chi_square_quantile(static_cast<int>(all.size() - lift.size()), kLiftConfidence);
        mu_input_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(step_inputs_.size()));
      }
    }
  } else {
    theta_ = Eigen::VectorXd::Zero(n + (rate_ ? m : 0));
  }
  if (solver_ && solver_->problem().nx() != theta_.size()) {
    throw std::invalid_argument("tube controller: the solver takes " + std::to_string(solver_->problem().nx()) +
                                " parameters, the law gives " + std::to_string(theta_.size()) +
                                (opt_.offset_free ? " (build it from artifact.qp(true))" : ""));
  }
  u_min_ = a.input_min;
  u_max_ = a.input_max;
  (void)m;
}

void TubeController::reset(const Eigen::VectorXd& x_tilde) {
  x_bar_ = a_.N_x.cwiseProduct(x_tilde);
  if (kalman_) {
    // The filter starts from the prior of a vehicle on its reference (zero error, no
    // disturbance) and takes the first measurement through its gain like every later
    // one; the nominal state starts on that prior (in prepare()). Starting at the raw
    // measurement put its noise into the nominal trajectory, which the QP then flew: a
    // servo-rate kick of 1.4 times its bound in the first 0.1 s (at the first estimate:
    // 1.003 times at twice the design noise). A row the first measurement puts far
    // outside its noise starts at that measurement, filter and nominal (prepare()).
    xi_.setZero();
    x_hat_.setZero();
    from_prior_ = true;
    std::fill(prior_refuted_.begin(), prior_refuted_.end(), 0);
    kf_step_ = 0;
  }
  d_hat_.setZero();
  c_hat_.setZero();
  d_res_.setZero();
  c_res_.setZero();
  d_kf_.setZero();
  c_kf_.setZero();
  if (monitor_) monitor_->reset();
  if (schedule_) schedule_->reset();
  std::fill(gate_run_.begin(), gate_run_.end(), 0);
  gate_have_prev_ = false;
  reopened_ = reopened_lift_ = false;
  step_window_.clear();
  if (step_sum_.size() > 0) step_sum_.setZero();
  std::fill(step_armed_.begin(), step_armed_.end(), 1);
  std::fill(step_pending_.begin(), step_pending_.end(), 0);
  w_ = kalman_ ? 1.0 : 0.0;
  u_s_.setZero();
  v_prev_.setZero();
  x_s_.setZero();
  have_prev_ = false;
  prev_off_law_ = false;
  reverted_ = false;
  if (solver_) solver_->reset();
}

const ControlStep& TubeController::step(const Eigen::VectorXd& x_tilde, const Eigen::VectorXd& u_r,
                                        bool optimizer_in_time) {
  const Eigen::VectorXd& p = prepare(x_tilde);
  return finish(u_r, solver_ ? &solver_->solve(p) : nullptr, optimizer_in_time);
}

const StartSchedule& TubeController::opening() const {
  static const StartSchedule none;
  const std::shared_ptr<const StartSchedule>& s =
      !reopened_ ? start_ : reopened_lift_ ? reopen_lift_[reopen_at_] : reopen_[reopen_at_];
  return s ? *s : none;
}

const Eigen::VectorXd& TubeController::innovation_sd_now() const {
  const std::vector<Eigen::VectorXd>& sd = opening().innovation_sds;
  return kf_step_ < sd.size() ? sd[kf_step_] : schedule_ ? schedule_->innovation_sd() : innov_sd_;
}

void TubeController::detect_step() {
  const Eigen::VectorXd& sd = innovation_sd_now();
  bool step = false;
  const bool classify = !sig_all_.empty();
  for (Eigen::Index j = 0; j < innov_.size(); ++j) {
    const double z = innov_(j) / sd(j);
    if (classify) step_z_(j) = z;
    step_sum_(j) = kStepMemory * step_sum_(j) + z;
    const double s = std::abs(step_sum_(j));
    auto& armed = step_armed_[static_cast<std::size_t>(j)];
    auto& pending = step_pending_[static_cast<std::size_t>(j)];
    if (s < 0.5 * kStepThreshold) armed = 1;  // re-armed once back well inside
    if (s <= kStepThreshold || !armed) {
      pending = 0;
    } else if (!pending) {
      pending = 1;  // past the threshold: a step if the next innovation confirms it
    } else if (z * step_sum_(j) > 0.0 && std::abs(z) > kStepConfirm) {
      step = true;  // a lasting bias the model cannot explain is one step, not one a period
      armed = pending = 0;
    } else {
      armed = pending = 0;  // a lone outlier decaying in the sum
    }
  }
  // The re-opened prior's gains are those of the noise scale flown: only where the noise
  // is read near it (re-opened with the design noise's gains at four times that noise,
  // 98 steps were read in the noise and the flight had 2678 violations instead of 139).
  const std::size_t at = schedule_ ? schedule_->index() : 0;
  const double scale = schedule_ ? schedule_->scale() : 1.0;
  const bool known_noise = monitor_ && at < reopen_.size() && monitor_->level() <= kStepNoiseLevel * scale;
  const bool starting = !reopened_ && start_ && kf_step_ < start_->gains.size();  // the start's own prior is open
  if (classify) step_window_.push(step_z_);
  if (!step || !known_noise || starting || prev_off_law_ || kf_step_ < kStepHold) return;
  bool lift = false;
  if (classify) {
    const StepSignature::Fit every = sig_all_[at].fit(step_window_);
    // A step older than the window (its best onset the window's oldest period) is left
    // to the steady gain, which has been reading it since (header).
    if (opt_.late_step_keeps_gain && every.onset >= kStepWindow) {
      out_.step_late = true;
      return;
    }
    // The lift only where every force does not explain the window significantly better.
    const double glr = every.statistic - sig_lift_[at].fit(step_window_).statistic;
    out_.step_horizontal_glr = glr;
    lift = glr <= lift_threshold_;
    if (!sig_input_.empty()) correct_input_step(at, every.statistic);
  }
  reopened_ = true;
  reopen_at_ = at;
  kf_step_ = 0;  // this period's update takes the re-opened prior's first gain
  out_.step_detected = true;
  reopened_lift_ = lift;
  out_.step_reopened_lift = lift;
}

void TubeController::correct_input_step(std::size_t at, double l_all) {
  // A step of the actuators, accepted where it explains kInputExplained of what every
  // force and residual explain; the prediction then takes the step's effect since its
  // onset, the step read along the directions the window determines (header).
  const StepSignature& sig = sig_input_[at];
  const StepSignature::Fit fit = sig.fit(step_window_);
  if (fit.onset < 1 || fit.statistic < kInputExplained * l_all) return;
  sig.read_step(step_window_, fit.onset, mu_input_);
  for (std::size_t i = 0; i < step_inputs_.size(); ++i) {
    // An input whose compensation would itself move a state by more than kInputKick of
    // its bound in one period (a servo's torque) is left to the re-opened gains.
    const auto j = static_cast<Eigen::Index>(i);
    if (B_a_.col(step_inputs_[i]).head(a_.measured).cwiseAbs().maxCoeff() * std::abs(mu_input_(j)) > kInputKick) {
      mu_input_(j) = 0.0;
    }
  }
  if (mu_input_.isZero(0.0)) return;
  xi_pred_.noalias() += sig.jump(fit.onset) * mu_input_;
  for (std::size_t j = 0; j < rows_.size(); ++j) innov_(static_cast<Eigen::Index>(j)) = x_n_(rows_[j]) - xi_pred_(rows_[j]);
  out_.step_input = true;
}

const Eigen::VectorXd& TubeController::prepare(const Eigen::VectorXd& x_tilde, bool consecutive) {
  x_n_ = a_.N_x.cwiseProduct(x_tilde);
  y_ = x_n_;
  // The filter's prediction of this measurement, and its innovation gate (header).
  out_.gated_rows = 0;
  out_.step_detected = out_.step_reopened_lift = false;
  out_.step_horizontal_glr = 0.0;
  out_.step_input = out_.step_late = false;
  const bool predicted = kalman_ && have_prev_ && consecutive && x_n_.allFinite();
  if (predicted) {
    xi_pred_.noalias() = A_a_ * xi_;
    xi_pred_.noalias() += B_a_ * u_prev_n_;
    const Eigen::VectorXd& sd = innovation_sd_now();
    const bool gate = opt_.innovation_gate && !prev_off_law_;
    for (std::size_t j : gated_rows_) {
      const int r = rows_[j];
      const auto i = static_cast<Eigen::Index>(j);
      const double nu = y_(r) - xi_pred_(r), bound = kInnovationGate_sigmas * sd(i);
      // A glitch arrives in one period; a real transient the filter lags grows its
      // innovation over several (header).
      const bool sudden = !gate_have_prev_ || std::abs(nu - gate_prev_innov_(i)) > bound;
      gate_prev_innov_(i) = nu;
      if (!gate) continue;
      int& run = gate_run_[j];
      if (std::abs(nu) <= bound) {
        run = 0;
      } else if (run > 0 ? run < kGateRun : sudden) {
        y_(r) = x_n_(r) = xi_pred_(r);
        ++run;
        ++out_.gated_rows;
      }
    }
  }
  gate_have_prev_ = predicted;
  // The one-step residual of the measurement r = y - A y_prev - B u_prev, once: the
  // residual observer's input and the noise monitor's (a non-finite state is left to
  // the solver's input check and reaches neither).
  const bool have_resid = (residual_ || monitor_) && have_prev_ && consecutive && y_.allFinite();
  if (have_resid) {
    resid_ = y_;
    resid_.noalias() -= a_.A * x_prev_;
    resid_.noalias() -= a_.B * u_prev_n_;
  }
  // The switched observer: which estimate flies this period (the filter's at the start;
  // the filter alone: always, its monitor reading the level only).
  const bool filter = kalman_ && (!monitor_ || monitor_->update(resid_, have_resid && !prev_off_law_));
  out_.filtered = filter;
  out_.noise_level = monitor_ ? monitor_->level() : 0.0;
  if (!kalman_) {
    w_ = 0.0;
  } else if (!monitor_ || from_prior_) {
    w_ = filter ? 1.0 : 0.0;
  } else if (monitor_->clean_at_start()) {
    w_ = 0.0;  // clean at the first check: the residual observer's start (below)
  } else {
    const double step = a_.sample_time / (filter ? kBlendToFilter_s : kBlendToResidual_s);
    w_ = filter ? std::min(1.0, w_ + step) : std::max(0.0, w_ - step);
  }
  out_.filter_weight = w_;
  if (kalman_ && x_n_.allFinite()) {
    const int p = a_.measured, ni = a_.n - p;
    if (have_prev_ && consecutive) {
      // The integral states are the controller's: the model's integral rows applied to
      // the previous estimate (the affine model, as the nominal's), not a measurement.
      next_.noalias() = a_.A * x_hat_;
      next_.noalias() += a_.B * u_prev_n_;
      next_.noalias() += a_.D * d_kf_;
      next_ += c_kf_;
      x_hat_.tail(ni) = next_.tail(ni);
      // xi_pred_: the prediction, above.
    } else if (from_prior_) {
      // The first period after reset(): predicted = the prior; the integrals measured.
      // A position or yaw row whose first measurement lies more than kPriorGate_sigmas
      // of its noise from the prior refutes it (a vehicle started or engaged off its
      // reference: a 0.3 m offset through the steady-state gain read as a load swing
      // and kicked the servo rates to twice their bound); that row starts at its
      // measurement. The other rows keep the prior: a vehicle starts near rest and
      // level, and sensor noise beyond the design's refuted their prior too often
      // (three times the design noise: a servo rate 2.8 times its bound, not 1.8).
      x_hat_.tail(ni) = x_n_.tail(ni);
      xi_pred_ = xi_;
      for (std::size_t j = 0; j < rows_.size(); ++j) {
        const int r = rows_[j];
        const StateKind kind = a_.kinds[static_cast<std::size_t>(r)];
        if (kind != StateKind::Position && kind != StateKind::Yaw) continue;
        if (std::abs(x_n_(r) - xi_pred_(r)) > kPriorGate_sigmas * a_.estimator_noise(static_cast<Eigen::Index>(j))) {
          xi_pred_(r) = x_n_(r);
          prior_refuted_[static_cast<std::size_t>(r)] = 1;
        }
      }
    } else {
      // A restart: the measured rows and the integrals from this state, the rest kept.
      x_hat_.tail(ni) = x_n_.tail(ni);
      xi_pred_ = xi_;
      for (int r : rows_) xi_pred_(r) = x_n_(r);
    }
    for (std::size_t j = 0; j < rows_.size(); ++j) innov_(static_cast<Eigen::Index>(j)) = x_n_(rows_[j]) - xi_pred_(rows_[j]);
    if (opt_.step_detection && have_prev_ && consecutive) {
      detect_step();
    } else {
      step_window_.clear();  // a gap: the window's innovations are no longer consecutive
    }
    xi_ = xi_pred_;
    // The start's schedule first (its prior, the design's noise), then the steady gain:
    // the design's, or the one for the monitor's noise level.
    const Eigen::MatrixXd& steady = schedule_ ? schedule_->update(monitor_->level()) : L_kf_;
    out_.filter_noise_scale = schedule_ ? schedule_->scale() : 1.0;
    const std::vector<Eigen::MatrixXd>& opening_gains = opening().gains;
    const Eigen::MatrixXd& gain = kf_step_ < opening_gains.size() ? opening_gains[kf_step_] : steady;
    ++kf_step_;
    xi_.noalias() += gain * innov_;
    x_hat_.head(p) = xi_.head(p);
    d_kf_ = xi_.segment(p, d_kf_.size());
    c_kf_.head(p).noalias() = E_c_ * xi_.tail(E_c_.cols());
    if (w_ >= 1.0) {
      x_n_ = x_hat_;  // the estimate, from here on
      d_hat_ = d_kf_;
      c_hat_ = c_kf_;
    } else if (w_ <= 0.0) {
      x_hat_.tail(ni) = y_.tail(ni);  // the integrals a switch to the filter continues from
    } else {
      x_n_ = w_ * x_hat_ + (1.0 - w_) * y_;  // blended with the residual observer's below
    }
    if (from_prior_) {
      // The nominal starts on the prior (the reference) wherever the first measurement
      // did not refute it, at the estimate where it did, and at the integrals. The first
      // estimate is the prior moved by L_0 times one noisy sample: a nominal started
      // there had the QP plan on that sample's noise (its first input 0.004 N m of servo
      // torque where the noise-free start asks none, a servo rate 1.003 times its bound
      // at twice the design noise); started on the prior, the tube gain, designed against
      // the noise, carries that deviation.
      x_bar_ = x_hat_;
      for (Eigen::Index i = 0; i < p; ++i) {
        if (!prior_refuted_[static_cast<std::size_t>(i)]) x_bar_(i) = 0.0;
      }
      from_prior_ = false;
    }
  }
  if (!residual_) {
    x_prev_ = y_;  // the filter alone: the monitor's residual next period
  } else {
    // Disturbance observer on the one-step residual of the measurement.
    if (have_resid) {
      d_raw_.noalias() = D_pinv_ * resid_;
      d_res_ += opt_.observer_gain * (d_raw_ - d_res_);
      resid_.noalias() -= a_.D * d_res_;  // what the force does not explain
      c_res_ += opt_.observer_gain * (resid_ - c_res_);
    }
    x_prev_ = y_;
    if (w_ <= 0.0) {
      d_hat_ = d_res_;
      c_hat_ = c_res_;
    } else if (w_ < 1.0) {
      d_hat_ = w_ * d_kf_ + (1.0 - w_) * d_res_;
      c_hat_ = w_ * c_kf_ + (1.0 - w_) * c_res_;
    }
  }
  if (opt_.offset_free) {
    x_s_.noalias() = Tx_ * d_hat_;
    u_s_.noalias() = Tu_ * d_hat_;
  }
  out_.in_state_box = a_.X.contains(x_n_);
  if (monitor_ && monitor_->clean_at_start() && x_n_.allFinite()) x_bar_ = x_n_;  // as reset() without the filter
  if (opt_.reinitialize_nominal && a_.x_bar.contains(x_n_)) x_bar_ = x_n_;
  e_ = x_n_ - x_bar_;
  dev_ = (e_ - a_.Z.c).cwiseAbs();  // distance from Z's centre, per state
  out_.in_tube = (dev_.array() <= z_half_.array() + 1e-12).all();
  Eigen::Index worst = 0;
  out_.tube_ratio = (dev_.array() / (z_half_.array() + 1e-300)).maxCoeff(&worst);
  out_.tube_worst = static_cast<int>(worst);
  out_.x_bar = x_bar_;
  out_.x_tilde = x_n_;
  out_.d_hat = d_hat_;
  if (!opt_.offset_free && !rate_) return x_bar_;
  theta_.head(a_.n) = x_bar_ - x_s_;  // x_s = 0 without the observer
  if (opt_.offset_free) {
    theta_.segment(a_.n, d_hat_.size()) = d_hat_;
    theta_.segment(a_.n + d_hat_.size(), a_.n) = c_hat_;
  }
  if (rate_) theta_.tail(a_.m) = v_prev_ - u_s_;  // u_hat's coordinates (mpc_qp.hpp)
  return theta_;
}

const ControlStep& TubeController::finish(const Eigen::VectorXd& u_r, const SolveResult* r, bool in_time) {
  if (r != nullptr) {
    out_.status = r->status;
    out_.iterations = r->iterations;
    out_.solve_us = r->solve_us;
  }
  out_.softened = r != nullptr && r->softened;
  out_.slack_max = out_.softened && r->slack_state >= 0 ? r->slack_max / a_.N_x(r->slack_state) : 0.0;
  out_.slack_state = out_.softened ? r->slack_state : -1;
  // The reversion's hysteresis on the error's largest ratio to its bound in X.
  if (opt_.revert_beyond > 0.0) {
    double worst = x_n_.allFinite() ? 0.0 : std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < x_n_.size(); ++i) {
      const double bound = std::max(x_n_(i) >= 0.0 ? a_.X.hi(i) : -a_.X.lo(i), 1e-300);
      worst = std::max(worst, std::abs(x_n_(i)) / bound);
    }
    if (worst > opt_.revert_beyond) {  // a non-finite error reverts too
      reverted_ = true;
    } else if (worst <= opt_.revert_within) {
      reverted_ = false;
    }
  }
  out_.reverted = reverted_;
  reverted_periods_ += reverted_;
  const bool usable =
      !reverted_ && in_time && r != nullptr && r->status == SolveStatus::Converged && r->z.allFinite();
  if (usable) {
    ub_ = r->z.head(a_.m) + u_s_;  // u_s = 0 without the observer
    u_n_ = ub_;
    u_n_.noalias() += a_.K * e_;
    out_.u_bar = ub_.cwiseQuotient(a_.N_u);
    next_.noalias() = a_.A * x_bar_;
    next_.noalias() += a_.B * ub_;  // nominal model (Mayne)
    out_.fallback = false;
  } else {
    // LQR fallback on the measured error (around the disturbance's steady state when
    // offset-free); the nominal state restarts from it.
    resid_ = x_n_ - x_s_;
    u_n_ = u_s_;
    u_n_.noalias() += (reverted_ ? a_.K : a_.K_lqr) * resid_;
    out_.u_bar.setZero();
    next_.noalias() = a_.A * x_n_;
    next_.noalias() += a_.B * u_n_;
    out_.fallback = true;
    ++fallbacks_;
  }
  // The rate weight's u(-1) next period: the nominal input, or the LQR's after a fallback.
  if (rate_) v_prev_ = usable ? ub_ : u_n_;
  if (opt_.offset_free) {  // the affine nominal model: + D d_hat + c_hat
    next_.noalias() += a_.D * d_hat_;
    next_ += c_hat_;
  }
  x_bar_ = next_;
  u_raw_ = u_r + u_n_.cwiseQuotient(a_.N_u);
  out_.u = u_raw_.cwiseMax(u_min_).cwiseMin(u_max_);
  out_.clipped = (out_.u - u_raw_).cwiseAbs().maxCoeff() > 0.0;
  clipped_ += out_.clipped;
  // The input the plant gets, in normalized error coordinates, for the observer.
  u_prev_n_ = (out_.u - u_r).cwiseProduct(a_.N_u);
  have_prev_ = out_.u.allFinite() && x_n_.allFinite();
  prev_off_law_ = out_.softened || out_.fallback;
  return out_;
}

}  // namespace tmpc
