#include "tmpc/runtime/tube_controller.hpp"

#include <cmath>
#include <stdexcept>

#include "tmpc/model/config.hpp"
#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {

void TubeControllerOptions::validate() const {
  if (!(observer_gain > 0.0 && observer_gain <= 1.0)) {
    throw std::invalid_argument("tube controller: observer_gain must be in (0, 1], got " + std::to_string(observer_gain));
  }
}

TubeControllerOptions tube_law_options(const Config& cfg, const std::string& law, double observer_gain) {
  TubeControllerOptions o;
  o.offset_free = cfg.tube_law.offset_free;
  o.observer_gain = cfg.tube_law.observer_gain;
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
  x_bar_ = Eigen::VectorXd::Zero(a.n);
  x_n_ = Eigen::VectorXd::Zero(a.n);
  e_ = Eigen::VectorXd::Zero(a.n);
  dev_ = Eigen::VectorXd::Zero(a.n);
  next_ = Eigen::VectorXd::Zero(a.n);
  x_s_ = Eigen::VectorXd::Zero(a.n);
  c_hat_ = Eigen::VectorXd::Zero(a.n);
  x_prev_ = Eigen::VectorXd::Zero(a.n);
  resid_ = Eigen::VectorXd::Zero(a.n);
  z_half_ = a.Z.radius();
  out_.x_bar = Eigen::VectorXd::Zero(a.n);
  if (opt_.offset_free) {
    const DisturbanceTarget t = a.disturbance_target();
    Tx_ = t.Tx;
    Tu_ = t.Tu;
    // The load's translational accelerations (velocity rows of x, y, z) observe the
    // force: the tilt and swing rows of D are dominated by servo and pendulum
    // mismatch, which biased the estimate by 0.1 to 0.3 N in the helix mission.
    D_pinv_ = disturbance_pseudo_inverse(a.D, {kNq + kX, kNq + kY, kNq + kZ});
    theta_ = Eigen::VectorXd::Zero(2 * a.n + kNd);
  } else {
    theta_ = Eigen::VectorXd::Zero(a.n);
  }
  if (solver_ && solver_->problem().nx() != theta_.size()) {
    throw std::invalid_argument("tube controller: the solver takes " + std::to_string(solver_->problem().nx()) +
                                " parameters, the law gives " + std::to_string(theta_.size()) +
                                (opt_.offset_free ? " (build it from artifact.qp(true))" : ""));
  }
  // Absolute actuator limits from the design's own configuration.
  const Config cfg = load_config_from_string(a.config_text, "artifact");
  u_min_ = cfg.input_min;
  u_max_ = cfg.input_max;
}

void TubeController::reset(const Eigen::VectorXd& x_tilde) {
  x_bar_ = a_.N_x.cwiseProduct(x_tilde);
  d_hat_.setZero();
  c_hat_.setZero();
  u_s_.setZero();
  x_s_.setZero();
  have_prev_ = false;
  if (solver_) solver_->reset();
}

const ControlStep& TubeController::step(const Eigen::VectorXd& x_tilde, const Eigen::Vector4d& u_r,
                                        bool optimizer_in_time) {
  const Eigen::VectorXd& p = prepare(x_tilde);
  return finish(u_r, solver_ ? &solver_->solve(p) : nullptr, optimizer_in_time);
}

const Eigen::VectorXd& TubeController::prepare(const Eigen::VectorXd& x_tilde, bool consecutive) {
  x_n_ = a_.N_x.cwiseProduct(x_tilde);
  out_.in_state_box = a_.X.contains(x_n_);
  if (opt_.offset_free) {
    // Disturbance observer on the one-step residual (a non-finite state is left to the
    // solver's input check and does not reach the estimate).
    if (have_prev_ && consecutive && x_n_.allFinite()) {
      resid_ = x_n_;
      resid_.noalias() -= a_.A * x_prev_;
      resid_.noalias() -= a_.B * u_prev_n_;
      d_raw_.noalias() = D_pinv_ * resid_;
      d_hat_ += opt_.observer_gain * (d_raw_ - d_hat_);
      resid_.noalias() -= a_.D * d_hat_;  // what the force does not explain
      c_hat_ += opt_.observer_gain * (resid_ - c_hat_);
    }
    x_s_.noalias() = Tx_ * d_hat_;
    u_s_.noalias() = Tu_ * d_hat_;
    x_prev_ = x_n_;
  }
  if (opt_.reinitialize_nominal && a_.x_bar.contains(x_n_)) x_bar_ = x_n_;
  e_ = x_n_ - x_bar_;
  dev_ = (e_ - a_.Z.c).cwiseAbs();  // distance from Z's centre, per state
  out_.in_tube = (dev_.array() <= z_half_.array() + 1e-12).all();
  Eigen::Index worst = 0;
  out_.tube_ratio = (dev_.array() / (z_half_.array() + 1e-300)).maxCoeff(&worst);
  out_.tube_worst = static_cast<int>(worst);
  out_.x_bar = x_bar_;
  out_.d_hat = d_hat_;
  if (!opt_.offset_free) return x_bar_;
  theta_.head(a_.n) = x_bar_ - x_s_;
  theta_.segment<kNd>(a_.n) = d_hat_;
  theta_.tail(a_.n) = c_hat_;
  return theta_;
}

const ControlStep& TubeController::finish(const Eigen::Vector4d& u_r, const SolveResult* r, bool in_time) {
  if (r != nullptr) {
    out_.status = r->status;
    out_.iterations = r->iterations;
    out_.solve_us = r->solve_us;
  }
  Eigen::Vector4d u_n;
  const bool usable = in_time && r != nullptr && r->status == SolveStatus::Converged && r->z.allFinite();
  if (usable) {
    const Eigen::Vector4d ub = r->u0() + u_s_;  // u_s = 0 without the observer
    u_n = ub + a_.K * e_;
    out_.u_bar = ub.cwiseQuotient(a_.N_u);
    next_.noalias() = a_.A * x_bar_ + a_.B * ub;  // nominal model (Mayne)
    out_.fallback = false;
  } else {
    // LQR fallback on the measured error (around the disturbance's steady state when
    // offset-free); the nominal state restarts from it.
    resid_ = x_n_ - x_s_;
    u_n = u_s_;
    u_n.noalias() += a_.K_lqr * resid_;
    out_.u_bar.setZero();
    next_.noalias() = a_.A * x_n_ + a_.B * u_n;
    out_.fallback = true;
    ++fallbacks_;
  }
  if (opt_.offset_free) {  // the affine nominal model: + D d_hat + c_hat
    next_.noalias() += a_.D * d_hat_;
    next_ += c_hat_;
  }
  x_bar_ = next_;
  const Eigen::Vector4d u = u_r + u_n.cwiseQuotient(a_.N_u);
  out_.u = u.cwiseMax(u_min_).cwiseMin(u_max_);
  out_.clipped = (out_.u - u).cwiseAbs().maxCoeff() > 0.0;
  clipped_ += out_.clipped;
  // The input the plant gets, in normalized error coordinates, for the observer.
  u_prev_n_ = (out_.u - u_r).cwiseProduct(a_.N_u);
  have_prev_ = out_.u.allFinite() && x_n_.allFinite();
  return out_;
}

}  // namespace tmpc
