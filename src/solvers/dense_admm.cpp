// The exact ADMM machinery (see dense_admm.hpp).
#include "dense_admm.hpp"
#include "solve_clock.hpp"

#include "tmpc/gpu/nesterov_restart.hpp"

#include <algorithm>
#include <cmath>

namespace tmpc::detail {

namespace {
constexpr double kPolishBand = 100.0;  // polish once both residuals are within this factor of the tolerance
template <class E>
inline double inf_norm(const Eigen::MatrixBase<E>& v) {  // no temporary for expressions
  return v.size() ? v.cwiseAbs().maxCoeff() : 0.0;
}
}  // namespace

DenseAdmm::DenseAdmm(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, const Eigen::VectorXd& lo0,
                     const Eigen::VectorXd& hi0, const SolverOptions& opt, std::vector<ShiftSegment> x_shift,
                     std::vector<ShiftSegment> row_shift)
    : H_(H), A_(A), opt_(opt), x_shift_(std::move(x_shift)), row_shift_(std::move(row_shift)) {
  const Eigen::Index n = H.rows(), m = A.rows();
  // Ruiz equilibration of [H A'; A 0]: rows/columns scaled to unit infinity norm.
  D_ = Eigen::VectorXd::Ones(n);
  E_ = Eigen::VectorXd::Ones(m);
  if (opt.equilibrate) {
    for (int pass = 0; pass < 15; ++pass) {
      Eigen::VectorXd dn(n), dm(m);
      for (Eigen::Index j = 0; j < n; ++j) {
        const double v = std::max(H_.col(j).cwiseAbs().maxCoeff(), m > 0 ? A_.col(j).cwiseAbs().maxCoeff() : 0.0);
        dn(j) = v > 1e-12 ? 1.0 / std::sqrt(v) : 1.0;
      }
      for (Eigen::Index i = 0; i < m; ++i) {
        const double v = A_.row(i).cwiseAbs().maxCoeff();
        dm(i) = v > 1e-12 ? 1.0 / std::sqrt(v) : 1.0;
      }
      H_ = dn.asDiagonal() * H_ * dn.asDiagonal();
      A_ = dm.asDiagonal() * A_ * dn.asDiagonal();
      D_ = D_.cwiseProduct(dn);
      E_ = E_.cwiseProduct(dm);
    }
    const double hmean = H_.cwiseAbs().colwise().maxCoeff().mean();
    c_ = hmean > 1e-12 ? 1.0 / hmean : 1.0;
    H_ *= c_;
  }
  rho0_ = rho_ = opt.rho > 0.0 ? opt.rho : opt.rho_scale * spectral_rho(H_, A_);
  equality_.assign(static_cast<std::size_t>(m), 0);
  for (Eigen::Index i = 0; i < m; ++i) equality_[static_cast<std::size_t>(i)] = lo0(i) == hi0(i);
  rho_vec_.resize(m);
  rho_inv_.resize(m);
  K_.resize(n, n);
  factor();  // LLT::compute sizes llt_ (a copy-assigned LLT(n) would copy its unset info)
  for (Eigen::VectorXd* v : {&x_, &xt_, &rhs_, &tmp_n_, &Hx_, &Aty_, &fs_, &xp_}) v->setZero(n);
  yp_.setZero(m);
  polish_ = ActiveSetPolish(static_cast<int>(n), static_cast<int>(m));
  schur_.setup(H_, A_);  // not for the CZ formulation (H singular): the dense polish stays
  order_.reserve(static_cast<std::size_t>(m));
  for (std::vector<int>* v : {&guess_, &seen_, &tried_guess_}) v->reserve(static_cast<std::size_t>(m));
  for (Eigen::VectorXd* v : {&z_, &y_, &zh_, &yh_, &zprev_, &yprev_, &zt_, &yhalf_, &tmp_m_, &Ax_, &los_, &his_, &y_check_, &dy_})
    v->setZero(m);
}

void DenseAdmm::factor() {
  for (Eigen::Index i = 0; i < rho_vec_.size(); ++i) {
    rho_vec_(i) = equality_[static_cast<std::size_t>(i)] ? 1e3 * rho_ : rho_;
    rho_inv_(i) = 1.0 / rho_vec_(i);
  }
  K_.noalias() = A_.transpose() * rho_vec_.asDiagonal() * A_;
  K_ += H_;
  K_.diagonal().array() += opt_.sigma;
  llt_.compute(K_);
}

bool DenseAdmm::try_polish(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, bool near) {
  guess_.clear();
  for (Eigen::Index i = 0; i < z_.size(); ++i) {
    const bool eq = equality_[static_cast<std::size_t>(i)];
    const bool up = eq || hi(i) - z_(i) < y_(i) * rho_inv_(i);   // OSQP's rule: u - z < y / rho
    const bool low = !up && z_(i) - lo(i) < -y_(i) * rho_inv_(i);  // z - l < -y / rho
    if (!up && !low) continue;
    const int s = up ? static_cast<int>(i) + 1 : -(static_cast<int>(i) + 1);
    guess_.push_back(s);  // within the reserved capacity (m)
  }
  // Never a guess that already failed. The dense polish (CZ) only once the residuals
  // are near and the guess has settled (the same at two checks in a row): a failed
  // attempt costs an LU of the KKT matrix. The Schur finish repairs a rough guess
  // (spurious rows, rows dependent on the true set, more rows than variables) in a few
  // cheap steps, so it is tried from the first check on.
  const bool settled = guess_ == seen_;
  seen_.assign(guess_.begin(), guess_.end());
  if (!schur_.ready() && !(near && settled)) return false;
  if (tried_ && guess_ == tried_guess_) return false;
  tried_ = true;
  tried_guess_.assign(guess_.begin(), guess_.end());
  if (schur_.ready()) {
    order_.clear();  // the strongest rows first
    for (int s : guess_) order_.emplace_back(-std::abs(y_(std::abs(s) - 1)), s);
    std::sort(order_.begin(), order_.end());
    schur_.clear();
    for (const auto& [strength, s] : order_) schur_.propose(std::abs(s) - 1, s > 0);
    return finish(f, lo, hi);
  }
  polish_.clear();
  for (int s : guess_) {
    if (!polish_.add(std::abs(s) - 1, s > 0)) return false;  // more rows than LICQ allows
  }
  return solve_guess(f, lo, hi);
}

bool DenseAdmm::finish(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  const bool ok = schur_.solve(f, lo, hi, 1e-9, opt_.polish_steps, xp_, yp_);
  finish_steps_ += schur_.steps();
  if (ok) accept(lo, hi);
  return ok;
}

bool DenseAdmm::solve_guess(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  if (schur_.ready()) {
    schur_.clear();
    for (int j = 0; j < polish_.size(); ++j) {
      schur_.propose(polish_.rows()[static_cast<std::size_t>(j)], polish_.signs()[static_cast<std::size_t>(j)] > 0);
    }
    return finish(f, lo, hi);
  }
  bool ok = polish_.solve(H_, A_, f, lo, hi, 1e-9, xp_, yp_);
  // A wrong guess: a few primal-dual active-set steps from its point.
  for (int step = 0; !ok && step < opt_.polish_refine && polish_.refine(lo, hi, 1e-9); ++step) {
    ok = polish_.solve(H_, A_, f, lo, hi, 1e-9, xp_, yp_);
  }
  if (ok) accept(lo, hi);
  return ok;
}

void DenseAdmm::accept(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  x_ = xp_;
  y_ = yp_;
  z_.noalias() = A_ * x_;
  z_ = z_.cwiseMax(lo).cwiseMin(hi);
  zt_ = z_;
}

bool DenseAdmm::primal_infeasible(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  dy_ = y_ - y_check_;
  y_check_ = y_;
  const double norm = inf_norm(dy_);
  if (opt_.eps_pinf <= 0.0 || !(norm > 1e-12)) return false;
  tmp_n_.noalias() = A_.transpose() * dy_;
  if (inf_norm(tmp_n_) > opt_.eps_pinf * norm) return false;
  double support = 0.0;  // hi'max(dy, 0) + lo'min(dy, 0); an infinite bound in the way: no certificate
  for (Eigen::Index i = 0; i < dy_.size(); ++i) {
    if (dy_(i) > 0.0) support += hi(i) * dy_(i);
    if (dy_(i) < 0.0) support += lo(i) * dy_(i);
  }
  return support <= -opt_.eps_pinf * norm;
}

bool DenseAdmm::crash(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, bool warm) {
  if (!schur_.ready()) return false;  // H singular (CZ): no unconstrained minimizer
  if (warm) {
    xp_ = x_;
  } else {
    schur_.unconstrained(f, xp_);
  }
  Ax_.noalias() = A_ * xp_;
  polish_.clear();
  // Rows at or beyond a bound, the farthest first, while there is room.
  for (;;) {
    Eigen::Index worst = -1;
    double worst_v = -1e-9;
    for (Eigen::Index i = 0; i < Ax_.size(); ++i) {
      const double v = std::max(Ax_(i) - hi(i), lo(i) - Ax_(i));
      if (v > worst_v) {
        worst_v = v;
        worst = i;
      }
    }
    if (worst < 0 || polish_.size() >= static_cast<int>(xp_.size())) break;
    polish_.add(static_cast<int>(worst), Ax_(worst) > hi(worst) - 1e-9);
    Ax_(worst) = 0.5 * (lo(worst) + hi(worst));  // taken
  }
  return solve_guess(f, lo, hi);
}

void DenseAdmm::shift(Eigen::VectorXd& v, const std::vector<ShiftSegment>& segs) {
  for (const ShiftSegment& s : segs) {
    for (int k = 0; k + 1 < s.count; ++k) {
      v.segment(s.offset + k * s.block, s.block) = v.segment(s.offset + (k + 1) * s.block, s.block);
    }
  }
}

void DenseAdmm::solve(const Eigen::VectorXd& f_in, const Eigen::VectorXd& lo_in, const Eigen::VectorXd& hi_in,
                      SolveResult& res) {
  const double t0 = now_us();
  // Scaled instance: f~ = c D f, bounds E lo, E hi (infinite bounds stay infinite).
  fs_ = c_ * D_.cwiseProduct(f_in);
  los_ = E_.cwiseProduct(lo_in);
  his_ = E_.cwiseProduct(hi_in);
  const Eigen::VectorXd& f = fs_;
  const Eigen::VectorXd& lo = los_;
  const Eigen::VectorXd& hi = his_;
  if (rho_ != rho0_) {  // every solve starts from the set-up penalty
    rho_ = rho0_;
    factor();
  }
  if (opt_.warm_start && have_previous_) {
    // Primal warm start (the previous solution shifted one step); the duals restart
    // at zero: shifted duals measured slower than cold on the case study.
    x_ = x_.cwiseProduct(D_);  // to original units, shift, back
    shift(x_, x_shift_);
    x_ = x_.cwiseQuotient(D_);
    z_ = z_.cwiseQuotient(E_);
    shift(z_, row_shift_);
    z_ = z_.cwiseProduct(E_).cwiseMax(lo).cwiseMin(hi);
    y_.setZero();
  } else {
    x_.setZero();
    z_ = Eigen::VectorXd::Zero(z_.size()).cwiseMax(lo).cwiseMin(hi);
    y_.setZero();
  }
  zh_ = z_;
  yh_ = y_;
  zprev_ = z_;
  yprev_ = y_;
  gpu::NesterovRestart<double> nesterov;  // shared with the GPU kernel
  y_check_ = y_;
  tried_ = false;
  finish_steps_ = 0;
  schur_.clear();  // no certificate from an earlier instance
  tried_guess_.clear();
  seen_.clear();
  res.restarts = 0;
  res.status = SolveStatus::MaxIterations;
  const double f_norm = inf_norm(f_in);
  int k = 1;
  if (opt_.crash_start && crash(f, lo, hi, opt_.warm_start && have_previous_)) {
    res.status = SolveStatus::Converged;
    k = 0;
    Hx_.noalias() = H_ * x_;
    Aty_.noalias() = A_.transpose() * y_;
    res.primal_residual = 0.0;
    res.dual_residual = inf_norm((Hx_ + f + Aty_).cwiseQuotient(D_)) / c_;
  }
  for (; k >= 1 && k <= opt_.max_iterations; ++k) {
    // x~ from the factored KKT matrix.
    tmp_m_ = rho_vec_.cwiseProduct(zh_) - yh_;
    rhs_.noalias() = A_.transpose() * tmp_m_;
    rhs_ += opt_.sigma * x_ - f;
    xt_ = llt_.solve(rhs_);
    zt_.noalias() = A_ * xt_;
    // Symmetric dual steps around the exact projection.
    yhalf_ = yh_ + opt_.r * rho_vec_.cwiseProduct(zt_ - zh_);
    tmp_m_ = zt_ + rho_inv_.cwiseProduct(yhalf_);
    z_ = tmp_m_.cwiseMax(lo).cwiseMin(hi);
    y_ = yhalf_ + opt_.s * rho_vec_.cwiseProduct(zt_ - z_);
    x_ = xt_;

    // Nesterov extrapolation with the residual restart (Algorithm 4.2).
    if (opt_.nesterov) {
      tmp_m_ = rho_vec_.cwiseProduct(z_ - zh_);
      tmp_n_.noalias() = A_.transpose() * tmp_m_;
      const double c = rho_inv_.cwiseProduct(y_ - yh_).norm() + tmp_n_.norm();
      double beta = 0.0;
      if (nesterov.accept(c, opt_.eta, beta)) {
        zh_ = z_ + beta * (z_ - zprev_);
        yh_ = y_ + beta * (y_ - yprev_);
      } else {
        zh_ = zprev_;
        yh_ = yprev_;
        ++res.restarts;
      }
      zprev_ = z_;
      yprev_ = y_;
    } else {
      zh_ = z_;
      yh_ = y_;
    }

    // Termination on the true residuals at (x, z, y), every check_every iterations.
    if (k % opt_.check_every != 0 && k < opt_.max_iterations) {
      if (opt_.time_budget_us > 0.0 && now_us() - t0 > opt_.time_budget_us) {
        res.status = SolveStatus::TimeBudget;
        break;
      }
      continue;
    }
    // Residuals in the original units: A x - z = E^-1 (A~x~ - z~),
    // H x + f + A'y = D^-1 (H~x~ + f~ + A~'y~) / c.
    Ax_ = zt_.cwiseQuotient(E_);
    Hx_.noalias() = H_ * x_;
    Aty_.noalias() = A_.transpose() * y_;
    Hx_ = Hx_.cwiseQuotient(D_) / c_;
    Aty_ = Aty_.cwiseQuotient(D_) / c_;
    tmp_m_ = z_.cwiseQuotient(E_);
    const double r_prim = inf_norm(Ax_ - tmp_m_);
    const double r_dual = inf_norm(Hx_ + f_in + Aty_);
    res.primal_residual = r_prim;
    res.dual_residual = r_dual;
    if (!std::isfinite(r_prim) || !std::isfinite(r_dual)) {
      res.status = SolveStatus::NumericalFailure;
      break;
    }
    const double eps_p = opt_.eps_abs + opt_.eps_rel * std::max(inf_norm(Ax_), inf_norm(tmp_m_));
    const double eps_d = opt_.eps_abs + opt_.eps_rel * std::max({inf_norm(Hx_), inf_norm(Aty_), f_norm});
    const bool within_eps = r_prim <= eps_p && r_dual <= eps_d;
    if (within_eps && !opt_.polish) {
      res.status = SolveStatus::Converged;
      break;
    }
    if (!within_eps && primal_infeasible(lo, hi)) {
      res.status = SolveStatus::Infeasible;
      break;
    }
    if (opt_.time_budget_us > 0.0 && now_us() - t0 > opt_.time_budget_us) {  // before a finish starts
      res.status = SolveStatus::TimeBudget;
      break;
    }
    // The finish runs at every check, also when the residuals already meet epsilon:
    // then the ADMM iterate is only eps-accurate, the finish makes it exact (the
    // iterate is returned only if the finish fails there).
    if (opt_.polish && try_polish(f, lo, hi, r_prim <= kPolishBand * eps_p && r_dual <= kPolishBand * eps_d)) {
      // x_, z_ = A x_, y_ now the exact KKT point of the guessed active set.
      Hx_.noalias() = H_ * x_;
      Aty_.noalias() = A_.transpose() * y_;
      res.primal_residual = 0.0;
      res.dual_residual = inf_norm((Hx_ + f + Aty_).cwiseQuotient(D_)) / c_;
      res.status = SolveStatus::Converged;
      break;
    }
    if (within_eps) {
      res.status = SolveStatus::Converged;
      break;
    }
    if (schur_.infeasible()) {  // the finish's dual ray, checked like OSQP's certificate
      res.status = SolveStatus::Infeasible;
      break;
    }
    // OSQP-style penalty rebalancing, every 25 iterations, with a cheap refactor.
    if (opt_.adaptive_rho && k % 25 == 0) {
      const double p = r_prim / (std::max(inf_norm(Ax_), inf_norm(tmp_m_)) + 1e-30);
      const double d = r_dual / (std::max({inf_norm(Hx_), inf_norm(Aty_), f_norm}) + 1e-30);
      const double ratio = std::sqrt(p / (d + 1e-30));
      if (ratio > 5.0 || ratio < 0.2) {
        rho_ *= std::min(std::max(ratio, 1e-3), 1e3);
        factor();
      }
    }
  }
  res.iterations = std::min(k, opt_.max_iterations);
  res.active_set_steps = finish_steps_;
  // Back to the original units: x = D x~, y = E y~ / c.
  res.z = x_.cwiseProduct(D_);
  res.y = y_.cwiseProduct(E_) / c_;
  Hx_.noalias() = H_ * x_;
  res.objective = (0.5 * x_.dot(Hx_) + f.dot(x_)) / c_;
  have_previous_ = res.status != SolveStatus::NumericalFailure;
  res.solve_us = now_us() - t0;
}

}  // namespace tmpc::detail
