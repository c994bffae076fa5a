// "admm-thesis": Algorithm 4.3 as written, with the loop condition fixed (E2).
#include <cmath>

#include <Eigen/Dense>

#include "tmpc/gpu/nesterov_restart.hpp"
#include "solve_clock.hpp"
#include "solvers_internal.hpp"

namespace tmpc::detail {


AdmmThesis::AdmmThesis(const MpcQpData& d, const ParametricQp& qp, const SolverOptions& opt)
    : n_(d.n), m_(d.m), N_(d.N), M_(d.M), P_(d.P), Pt_(d.P.transpose()), Q_(d.Q), Wx_(d.Wx()), Wu_(d.Wu()), qp_(qp),
      opt_(opt) {
  // The thesis gives no rule for rho (its future work asks for one): the plain
  // spectral rule; the calibration of the exact variant stalls this one, whose only
  // stopping test is the equality residual Gamma.
  rho_ = opt.rho > 0.0 ? opt.rho : spectral_rho(qp.H, qp.A);
  opt_.nesterov = true;  // part of Algorithm 4.3
  // u-step matrix (4.25): H1 = P' rho P + 2 W_u (dense).
  H1_inv_ = (rho_ * Pt_ * P_ + 2.0 * Wu_).inverse();
  // x-step matrix (4.28): H2 = rho I + 2 W_x, block diagonal: diagonal stage blocks
  // (diagonal Sigma_rho) and the dense terminal block.
  H2_diag_inv_ = (rho_ + 2.0 * d.Sigma_rho.diagonal().array()).inverse().matrix();
  H2_last_inv_ = (rho_ * Eigen::MatrixXd::Identity(n_, n_) + 2.0 * d.L).inverse();
  xlo_.resize(N_ * n_);
  xhi_.resize(N_ * n_);
  for (int i = 0; i < N_; ++i) {
    xlo_.segment(i * n_, n_) = d.x_bar.lo;
    xhi_.segment(i * n_, n_) = d.x_bar.hi;
  }
  ulo_.resize(M_ * m_);
  uhi_.resize(M_ * m_);
  for (int i = 0; i < M_; ++i) {
    ulo_.segment(i * m_, m_) = d.u_bar.lo;
    uhi_.segment(i * m_, m_) = d.u_bar.hi;
  }
  xlo0_ = xlo_;
  xhi0_ = xhi_;
  ulo0_ = ulo_;
  uhi0_ = uhi_;
  nd_ = d.disturbances();
  Tx_ = d.Tx;
  Tu_ = d.Tu;
  Phi_ = d.Phi;
  xs_.setZero(n_);
  us_.setZero(m_);
  for (Eigen::VectorXd* v : {&x_, &lam_, &xe_, &lame_, &xprev_, &lamprev_, &Qx0_, &Pu_, &g_, &t_n_}) v->setZero(N_ * n_);
  for (Eigen::VectorXd* v : {&u_, &t_u_}) v->setZero(M_ * m_);
  f_.resize(qp.nz());
  res_.z.resize(qp.nz());
  res_.y.setZero(qp.nc());
}

const SolveResult& AdmmThesis::solve(const Eigen::VectorXd& x0) {
  if (!valid_state(x0, qp_.nx(), res_)) return res_;
  const double t0 = now_us();
  Qx0_.noalias() = Q_ * x0.head(n_);
  if (nd_ > 0) {  // the sets around the disturbance's steady state, the offset's response
    Qx0_.noalias() += Phi_ * x0.tail(n_);
    xs_.noalias() = Tx_ * x0.segment(n_, nd_);
    us_.noalias() = Tu_ * x0.segment(n_, nd_);
    for (int i = 0; i < N_; ++i) {
      xlo_.segment(i * n_, n_) = xlo0_.segment(i * n_, n_) - xs_;
      xhi_.segment(i * n_, n_) = xhi0_.segment(i * n_, n_) - xs_;
    }
    for (int i = 0; i < M_; ++i) {
      ulo_.segment(i * m_, m_) = ulo0_.segment(i * m_, m_) - us_;
      uhi_.segment(i * m_, m_) = uhi0_.segment(i * m_, m_) - us_;
    }
  }
  if (opt_.warm_start && have_previous_) {
    for (int k = 0; k + 1 < M_; ++k) u_.segment(k * m_, m_) = u_.segment((k + 1) * m_, m_);
    for (int k = 0; k + 1 < N_; ++k) {
      x_.segment(k * n_, n_) = x_.segment((k + 1) * n_, n_);
      lam_.segment(k * n_, n_) = lam_.segment((k + 1) * n_, n_);
    }
  } else {
    // Algorithm 4.3 initialization: lambda = 0, u = 0 (x from the prediction).
    u_.setZero();
    lam_.setZero();
    x_ = Qx0_;
  }
  xe_ = x_;
  lame_ = lam_;
  xprev_ = x_;
  lamprev_ = lam_;
  gpu::NesterovRestart<double> nesterov;  // shared with the GPU kernel
  res_.restarts = 0;
  res_.status = SolveStatus::MaxIterations;
  int k = 1;
  for (; k <= opt_.max_iterations; ++k) {
    // u-step (4.32), (4.25)-(4.26): unconstrained minimizer of the dense H1, clipped.
    g_ = xe_ - Qx0_ + lame_;
    t_u_.noalias() = Pt_ * g_;
    u_.noalias() = H1_inv_ * t_u_;
    u_ *= rho_;
    u_ = u_.cwiseMax(ulo_).cwiseMin(uhi_);
    Pu_.noalias() = P_ * u_;
    // First dual step (4.33).
    lam_ = lame_ + opt_.r * (xe_ - Pu_ - Qx0_);
    // x-step (4.22), (4.27)-(4.28): (rho + 2 W_x)^-1 rho (P u + Q x0 - lambda), clipped.
    g_ = rho_ * (Pu_ + Qx0_ - lam_);
    for (int i = 0; i + 1 < N_; ++i) x_.segment(i * n_, n_) = H2_diag_inv_.cwiseProduct(g_.segment(i * n_, n_));
    x_.segment((N_ - 1) * n_, n_).noalias() = H2_last_inv_ * g_.segment((N_ - 1) * n_, n_);
    x_ = x_.cwiseMax(xlo_).cwiseMin(xhi_);
    // Gamma and the second dual step (4.23).
    t_n_ = x_ - Pu_ - Qx0_;
    lam_ += opt_.s * t_n_;
    res_.primal_residual = t_n_.cwiseAbs().maxCoeff();
    // Residual measure (4.34) and the restart of Algorithm 4.2.
    g_ = x_ - xe_;
    t_u_.noalias() = Pt_ * g_;
    const double c = (lam_ - lame_).norm() + rho_ * t_u_.norm();
    res_.dual_residual = rho_ * t_u_.cwiseAbs().maxCoeff();
    double beta = 0.0;
    if (opt_.nesterov && nesterov.accept(c, opt_.eta, beta)) {
      xe_ = x_ + beta * (x_ - xprev_);
      lame_ = lam_ + beta * (lam_ - lamprev_);
    } else if (opt_.nesterov) {
      xe_ = xprev_;
      lame_ = lamprev_;
      ++res_.restarts;
    } else {
      xe_ = x_;
      lame_ = lam_;
    }
    xprev_ = x_;
    lamprev_ = lam_;
    if (!std::isfinite(c)) {
      res_.status = SolveStatus::NumericalFailure;
      break;
    }
    // E2: iterate while ||Gamma||_inf > epsilon.
    if (res_.primal_residual <= opt_.eps_abs) {
      res_.status = SolveStatus::Converged;
      break;
    }
    if (opt_.time_budget_us > 0.0 && now_us() - t0 > opt_.time_budget_us) {
      res_.status = SolveStatus::TimeBudget;
      break;
    }
  }
  res_.iterations = std::min(k, opt_.max_iterations);
  res_.z = u_;
  f_ = qp_.f0;
  f_.noalias() += qp_.F * x0;  // the objective needs f only, not the bounds
  t_u_.noalias() = qp_.H * u_;
  res_.objective = 0.5 * u_.dot(t_u_) + f_.dot(u_);
  have_previous_ = res_.status != SolveStatus::NumericalFailure;
  res_.solve_us = now_us() - t0;
  return res_;
}

}  // namespace tmpc::detail
