#include "tmpc/runtime/tube_controller.hpp"

#include "tmpc/model/config.hpp"

namespace tmpc {

TubeController::TubeController(const ControllerArtifact& a, std::unique_ptr<QpSolver> solver, TubeControllerOptions opt)
    : a_(a), solver_(std::move(solver)), opt_(opt) {
  x_bar_ = Eigen::VectorXd::Zero(a.n);
  x_n_ = Eigen::VectorXd::Zero(a.n);
  e_ = Eigen::VectorXd::Zero(a.n);
  dev_ = Eigen::VectorXd::Zero(a.n);
  next_ = Eigen::VectorXd::Zero(a.n);
  z_half_ = a.Z.radius();
  out_.x_bar = Eigen::VectorXd::Zero(a.n);
  // Absolute actuator limits from the design's own configuration.
  const Config cfg = load_config_from_string(a.config_text, "artifact");
  u_min_ = cfg.input_min;
  u_max_ = cfg.input_max;
}

void TubeController::reset(const Eigen::VectorXd& x_tilde) {
  x_bar_ = a_.N_x.cwiseProduct(x_tilde);
  if (solver_) solver_->reset();
}

const ControlStep& TubeController::step(const Eigen::VectorXd& x_tilde, const Eigen::Vector4d& u_r,
                                        bool optimizer_in_time) {
  const Eigen::VectorXd& xb = prepare(x_tilde);
  return finish(u_r, solver_ ? &solver_->solve(xb) : nullptr, optimizer_in_time);
}

const Eigen::VectorXd& TubeController::prepare(const Eigen::VectorXd& x_tilde) {
  x_n_ = a_.N_x.cwiseProduct(x_tilde);
  out_.in_state_box = a_.X.contains(x_n_);
  if (opt_.reinitialize_nominal && a_.x_bar.contains(x_n_)) x_bar_ = x_n_;
  e_ = x_n_ - x_bar_;
  dev_ = (e_ - a_.Z.c).cwiseAbs();  // distance from Z's centre, per state
  out_.in_tube = (dev_.array() <= z_half_.array() + 1e-12).all();
  Eigen::Index worst = 0;
  out_.tube_ratio = (dev_.array() / (z_half_.array() + 1e-300)).maxCoeff(&worst);
  out_.tube_worst = static_cast<int>(worst);
  out_.x_bar = x_bar_;
  return x_bar_;
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
    const Eigen::Vector4d ub = r->u0();
    u_n = ub + a_.K * e_;
    out_.u_bar = ub.cwiseQuotient(a_.N_u);
    next_.noalias() = a_.A * x_bar_ + a_.B * ub;  // nominal model (Mayne)
    x_bar_ = next_;
    out_.fallback = false;
  } else {
    // LQR fallback on the measured error; the nominal state restarts from it.
    u_n = a_.K_lqr * x_n_;
    out_.u_bar.setZero();
    next_.noalias() = a_.A * x_n_ + a_.B * u_n;
    x_bar_ = next_;
    out_.fallback = true;
    ++fallbacks_;
  }
  const Eigen::Vector4d u = u_r + u_n.cwiseQuotient(a_.N_u);
  out_.u = u.cwiseMax(u_min_).cwiseMin(u_max_);
  out_.clipped = (out_.u - u).cwiseAbs().maxCoeff() > 0.0;
  clipped_ += out_.clipped;
  return out_;
}

}  // namespace tmpc
