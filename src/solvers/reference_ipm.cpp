// "reference": dense primal-dual interior point (Mehrotra) and an active-set polish.
#include <cmath>

#include "solvers_internal.hpp"
#include "solve_clock.hpp"

namespace tmpc::detail {


ReferenceQp::ReferenceQp(const ParametricQp& qp, const SolverOptions& opt)
    : qp_(qp), opt_(opt), nz_(qp.nz()), nc_(qp.nc()), polish_(qp.nz(), qp.nc()) {
  f_.resize(nz_);
  lo_.resize(nc_);
  hi_.resize(nc_);
  for (Eigen::VectorXd* v : {&z_, &dz_, &rd_, &t2_}) v->setZero(nz_);
  for (Eigen::VectorXd* v : {&lam_, &s_, &dlam_, &ds_, &rp_, &rc_, &w_, &Gz_, &h_}) v->setZero(2 * nc_);
  Mred_.resize(nz_, nz_);
  AtW_.resize(nz_, nc_);
  // Sized by a first factorization: an LLT(n) leaves its info unset, which copying
  // it reads (UBSan: an invalid enum value).
  llt_.compute(Eigen::MatrixXd::Identity(nz_, nz_));
  active_row_.assign(static_cast<std::size_t>(2 * nc_), 0);
  res_.z.resize(nz_);
  res_.y.resize(nc_);
}

const SolveResult& ReferenceQp::solve(const Eigen::VectorXd& x0) {
  if (!valid_state(x0, qp_.nx(), res_)) return res_;
  const double t0 = now_us();
  qp_.instance_into(x0, f_, lo_, hi_);
  const Eigen::MatrixXd& A = qp_.A;
  // G z <= h: rows i (a_i'z <= hi_i) and nc + i (-a_i'z <= -lo_i); infinite bounds drop out.
  int m = 0;
  for (int i = 0; i < nc_; ++i) {
    active_row_[static_cast<std::size_t>(i)] = std::isfinite(hi_(i));
    active_row_[static_cast<std::size_t>(nc_ + i)] = std::isfinite(lo_(i));
    h_(i) = active_row_[static_cast<std::size_t>(i)] ? hi_(i) : 0.0;
    h_(nc_ + i) = active_row_[static_cast<std::size_t>(nc_ + i)] ? -lo_(i) : 0.0;
    m += active_row_[static_cast<std::size_t>(i)] + active_row_[static_cast<std::size_t>(nc_ + i)];
  }
  z_.setZero();
  for (int i = 0; i < 2 * nc_; ++i) {
    const bool on = active_row_[static_cast<std::size_t>(i)];
    lam_(i) = on ? 1.0 : 0.0;
    s_(i) = on ? std::max(1.0, h_(i)) : 1.0;  // the slack of z = 0 where it is positive
  }
  auto G_times = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) {  // out = G v (masked)
    out.head(nc_).noalias() = A * v;
    out.tail(nc_) = -out.head(nc_);
    for (int i = 0; i < 2 * nc_; ++i) {
      if (!active_row_[static_cast<std::size_t>(i)]) out(i) = 0.0;
    }
  };
  auto Gt_times = [&](const Eigen::VectorXd& v, Eigen::VectorXd& out) {  // out = G'v
    w_.head(nc_) = v.head(nc_) - v.tail(nc_);
    out.noalias() = A.transpose() * w_.head(nc_);
  };
  const double scale_d = 1.0 + f_.cwiseAbs().maxCoeff();
  const double h_scale = qp_.H.diagonal().cwiseAbs().maxCoeff();
  const double scale_p = 1.0 + h_.cwiseAbs().maxCoeff();
  res_.status = SolveStatus::MaxIterations;
  int it = 0;
  for (; it < 100; ++it) {
    G_times(z_, Gz_);
    rp_ = Gz_ + s_ - h_;
    for (int i = 0; i < 2 * nc_; ++i) {
      if (!active_row_[static_cast<std::size_t>(i)]) rp_(i) = 0.0;
    }
    Gt_times(lam_, t2_);
    rd_.noalias() = qp_.H * z_;
    rd_ += f_ + t2_;
    const double mu = m > 0 ? s_.dot(lam_) / m : 0.0;
    res_.primal_residual = rp_.cwiseAbs().maxCoeff();
    res_.dual_residual = rd_.cwiseAbs().maxCoeff();
    if (res_.dual_residual <= 1e-10 * scale_d && res_.primal_residual <= 1e-10 * scale_p && mu <= 1e-13) {
      res_.status = SolveStatus::Converged;
      break;
    }
    if (!std::isfinite(mu) || !std::isfinite(res_.dual_residual)) {
      res_.status = SolveStatus::NumericalFailure;
      break;
    }
    // Reduced matrix H + G' S^-1 Lambda G = H + A' diag(d_up + d_lo) A.
    for (int i = 0; i < nc_; ++i) {
      const double d_up = active_row_[static_cast<std::size_t>(i)] ? lam_(i) / s_(i) : 0.0;
      const double d_lo = active_row_[static_cast<std::size_t>(nc_ + i)] ? lam_(nc_ + i) / s_(nc_ + i) : 0.0;
      AtW_.col(i) = A.row(i).transpose() * (d_up + d_lo);
    }
    Mred_.noalias() = AtW_ * A;
    Mred_ += qp_.H;
    // A relative 1e-14 regularization keeps the factorization defined when lambda/s
    // spans many decades near the solution.
    Mred_.diagonal().array() += 1e-14 * h_scale;
    llt_.compute(Mred_);
    if (llt_.info() != Eigen::Success) {
      res_.status = SolveStatus::NumericalFailure;
      break;
    }
    // Predictor (sigma = 0), then the corrector with Mehrotra's centering.
    double sigma_mu = 0.0;
    double alpha = 1.0;
    for (int pass = 0; pass < 2; ++pass) {
      for (int i = 0; i < 2 * nc_; ++i) {
        if (!active_row_[static_cast<std::size_t>(i)]) {
          rc_(i) = 0.0;
          continue;
        }
        rc_(i) = s_(i) * lam_(i) - sigma_mu + (pass == 1 ? ds_(i) * dlam_(i) : 0.0);
      }
      // t = S^-1 (-rc + Lambda rp); rhs = -rd - G't.
      Eigen::VectorXd& t = dlam_;  // reuse as scratch
      for (int i = 0; i < 2 * nc_; ++i) {
        t(i) = active_row_[static_cast<std::size_t>(i)] ? (-rc_(i) + lam_(i) * rp_(i)) / s_(i) : 0.0;
      }
      Gt_times(t, t2_);
      dz_ = -rd_ - t2_;
      llt_.solveInPlace(dz_);
      G_times(dz_, Gz_);
      for (int i = 0; i < 2 * nc_; ++i) {
        if (!active_row_[static_cast<std::size_t>(i)]) {
          ds_(i) = 0.0;
          dlam_(i) = 0.0;
          continue;
        }
        ds_(i) = -rp_(i) - Gz_(i);
        dlam_(i) = (-rc_(i) - lam_(i) * ds_(i)) / s_(i);
      }
      // Largest step keeping s, lambda >= 0.
      alpha = 1.0;
      for (int i = 0; i < 2 * nc_; ++i) {
        if (!active_row_[static_cast<std::size_t>(i)]) continue;
        if (ds_(i) < 0.0) alpha = std::min(alpha, -s_(i) / ds_(i));
        if (dlam_(i) < 0.0) alpha = std::min(alpha, -lam_(i) / dlam_(i));
      }
      if (pass == 0) {
        double mu_aff = 0.0;
        for (int i = 0; i < 2 * nc_; ++i) {
          if (active_row_[static_cast<std::size_t>(i)]) mu_aff += (s_(i) + alpha * ds_(i)) * (lam_(i) + alpha * dlam_(i));
        }
        mu_aff /= std::max(m, 1);
        const double sigma = std::pow(mu_aff / std::max(mu, 1e-300), 3.0);
        sigma_mu = sigma * mu;
      }
    }
    alpha = std::min(1.0, 0.99 * alpha);
    z_ += alpha * dz_;
    s_ += alpha * ds_;
    lam_ += alpha * dlam_;
    if (opt_.time_budget_us > 0.0 && now_us() - t0 > opt_.time_budget_us) {
      res_.status = SolveStatus::TimeBudget;
      break;
    }
  }
  res_.iterations = it;
  res_.z = z_;
  res_.y = lam_.head(nc_) - lam_.tail(nc_);
  // The active-set polish makes the point exact; it also rescues a run that stalled
  // short of the interior-point tolerance (it only accepts a verified KKT point).
  // A factorization that broke down near the solution (lambda/s over 20 decades) is
  // also polished: the polish only accepts a verified KKT point.
  if (res_.status != SolveStatus::TimeBudget) {
    if (polish()) {
      res_.status = SolveStatus::Converged;
    } else if (res_.status == SolveStatus::MaxIterations || res_.status == SolveStatus::NumericalFailure) {
      // Accept a stalled run, or one whose factorization broke down at the end, whose
      // KKT residuals already meet 1e-9 (degenerate active sets the polish refuses:
      // duplicated rows and equalities, where arm64's fused multiply-adds ended the
      // iteration one step from where x86-64's rounding converged).
      double comp = 0.0;
      for (int i = 0; i < 2 * nc_; ++i) comp = std::max(comp, active_row_[static_cast<std::size_t>(i)] ? s_(i) * lam_(i) : 0.0);
      if (res_.dual_residual <= 1e-9 * scale_d && res_.primal_residual <= 1e-9 * scale_p && comp <= 1e-9 * scale_d) {
        res_.status = SolveStatus::Converged;
      }
    }
  }
  t2_.noalias() = qp_.H * res_.z;
  res_.objective = 0.5 * res_.z.dot(t2_) + f_.dot(res_.z);
  res_.restarts = 0;
  res_.solve_us = now_us() - t0;
  return res_;
}

bool ReferenceQp::polish() {
  // Active set from the interior-point solution (lambda_i > s_i), else from the
  // rows whose slack at z is below 1e-7 of the bound's scale.
  if (polish_with(false)) return true;
  return polish_with(true);
}

bool ReferenceQp::polish_with(bool primal_activity) {
  polish_.clear();
  Gz_.head(nc_).noalias() = qp_.A * z_;
  for (int i = 0; i < nc_; ++i) {
    bool up, low;
    if (primal_activity) {
      up = active_row_[static_cast<std::size_t>(i)] && hi_(i) - Gz_(i) <= 1e-7 * (1.0 + std::abs(hi_(i)));
      low = !up && active_row_[static_cast<std::size_t>(nc_ + i)] && Gz_(i) - lo_(i) <= 1e-7 * (1.0 + std::abs(lo_(i)));
    } else {
      up = active_row_[static_cast<std::size_t>(i)] && lam_(i) > s_(i);
      low = active_row_[static_cast<std::size_t>(nc_ + i)] && lam_(nc_ + i) > s_(nc_ + i);
    }
    if ((up || low) && !polish_.add(i, up)) return false;  // more than LICQ allows
  }
  return polish_.solve(qp_.H, qp_.A, f_, lo_, hi_, 1e-10, res_.z, res_.y);
}

}  // namespace tmpc::detail
