// Active-set finish on the Schur complement (see schur_active_set.hpp).
#include "schur_active_set.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace tmpc::detail {

bool SchurActiveSet::setup(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, Eigen::Index g_limit) {
  const Eigen::LLT<Eigen::MatrixXd> llt(H);
  ready_ = llt.info() == Eigen::Success && H.rows() > 0;
  if (!ready_) return false;
  nz_ = static_cast<int>(H.rows());
  Hinv_ = llt.solve(Eigen::MatrixXd::Identity(H.rows(), H.cols()));
  At_ = A.transpose();
  W_ = Hinv_ * At_;
  // G = A H^-1 A' makes A z an update of k columns instead of an m x n product.
  const Eigen::Index m = A.rows();
  G_.resize(0, 0);
  if (m * m <= g_limit) G_ = A * W_;
  Au_.setZero(m);
  u_.setZero(nz_);
  zc_.setZero(nz_);
  dz_.setZero(nz_);
  Az_.setZero(A.rows());
  const int cap = std::min(nz_, 128);
  L_.setZero(cap, cap);
  ya_.setZero(cap);
  rhs_.setZero(cap);
  w_.setZero(cap);
  for (std::vector<int>* v : {&set_, &rebuild_}) v->reserve(static_cast<std::size_t>(cap));
  cand_.reserve(static_cast<std::size_t>(A.rows()));
  in_set_.assign(static_cast<std::size_t>(A.rows()), 0);
  return true;
}

bool SchurActiveSet::push(int s) {
  const int i = row_of(s);
  const int j = static_cast<int>(set_.size());
  if (in_set_[static_cast<std::size_t>(i)] || j >= L_.rows()) return false;
  for (int l = 0; l < j; ++l) w_(l) = W_.col(i).dot(At_.col(row_of(set_[static_cast<std::size_t>(l)])));
  const double d0 = W_.col(i).dot(At_.col(i));
  L_.topLeftCorner(j, j).triangularView<Eigen::Lower>().solveInPlace(w_.head(j));
  const double d = d0 - w_.head(j).squaredNorm();
  if (!(d > 1e-9 * d0)) return false;  // dependent on the set (or a zero row)
  L_.row(j).head(j) = w_.head(j).transpose();
  L_(j, j) = std::sqrt(d);
  set_.push_back(s);
  in_set_[static_cast<std::size_t>(i)] = 1;
  return true;
}

void SchurActiveSet::remove(int j) {
  rebuild_.assign(set_.begin(), set_.end());  // within the reserved capacity
  rebuild_.erase(rebuild_.begin() + j);
  for (int s : set_) in_set_[static_cast<std::size_t>(row_of(s))] = 0;
  set_.clear();
  for (int s : rebuild_) push(s);  // a subset of independent rows stays independent
}

void SchurActiveSet::solve_set(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  const int k = static_cast<int>(set_.size());
  zc_ = u_;
  ya_.head(k).setZero();
  for (int pass = 0; pass < 2; ++pass) {  // the second pass refines on the set's residual
    for (int j = 0; j < k; ++j) rhs_(j) = At_.col(row_of(set_[static_cast<std::size_t>(j)])).dot(zc_) - bound(j, lo, hi);
    L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(rhs_.head(k));
    L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(rhs_.head(k));
    ya_.head(k) += rhs_.head(k);
    for (int j = 0; j < k; ++j) zc_.noalias() -= rhs_(j) * W_.col(row_of(set_[static_cast<std::size_t>(j)]));
  }
  if (G_.size() == 0) {
    Az_.noalias() = At_.transpose() * zc_;
    az_direct_ = true;
    return;
  }
  Az_ = Au_;  // A z = A u - G_a y_a
  for (int j = 0; j < k; ++j) Az_.noalias() -= ya_(j) * G_.col(row_of(set_[static_cast<std::size_t>(j)]));
  az_direct_ = k == 0;
}

int SchurActiveSet::most_violated(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double feas_tol) const {
  int join = 0;
  double viol = feas_tol;
  for (Eigen::Index i = 0; i < Az_.size(); ++i) {
    if (in_set_[static_cast<std::size_t>(i)]) continue;
    if (Az_(i) - hi(i) > viol) {
      viol = Az_(i) - hi(i);
      join = static_cast<int>(i) + 1;
    } else if (lo(i) - Az_(i) > viol) {
      viol = lo(i) - Az_(i);
      join = -(static_cast<int>(i) + 1);
    }
  }
  return join;
}

void SchurActiveSet::drop(int j) {
  const int k = static_cast<int>(set_.size());
  for (int l = j; l + 1 < k; ++l) ya_(l) = ya_(l + 1);
  remove(j);
}

int SchurActiveSet::most_negative(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) const {
  const int k = static_cast<int>(set_.size());
  const double ymax = k > 0 ? ya_.head(k).cwiseAbs().maxCoeff() : 0.0;
  int leave = -1;
  double worst = -1e-10 * std::max(1.0, ymax);
  for (int j = 0; j < k; ++j) {
    const int s = set_[static_cast<std::size_t>(j)];
    const int i = row_of(s);
    if (lo(i) == hi(i)) continue;  // an equality row's multiplier has either sign
    const double v = s > 0 ? ya_(j) : -ya_(j);
    if (v < worst) {
      worst = v;
      leave = j;
    }
  }
  return leave;
}

bool SchurActiveSet::certify(int p, double sp, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  // The dual ray of the step: dy = -w on the set, sp on p. Checked as OSQP's
  // certificate, from its definition: ||A'dy|| <= eps ||dy|| and
  // hi'max(dy, 0) + lo'min(dy, 0) <= -eps ||dy|| (inf-norms, eps = 1e-6).
  const int k = static_cast<int>(set_.size());
  dz_ = sp * At_.col(p);
  double norm = 1.0, support = sp * (sp > 0 ? hi(p) : lo(p));
  for (int j = 0; j < k; ++j) {
    const int i = row_of(set_[static_cast<std::size_t>(j)]);
    const double d = -w_(j);
    dz_.noalias() += d * At_.col(i);
    norm = std::max(norm, std::abs(d));
    if (d > 0.0) support += d * hi(i);
    if (d < 0.0) support += d * lo(i);
  }
  return dz_.cwiseAbs().maxCoeff() <= 1e-6 * norm && support <= -1e-6 * norm;
}

bool SchurActiveSet::solve(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                           double feas_tol, int max_steps, Eigen::VectorXd& z, Eigen::VectorXd& y) {
  steps_ = 0;
  infeasible_ = false;
  if (!ready_) return false;
  unconstrained(f, u_);
  if (G_.size() != 0) Au_.noalias() = At_.transpose() * u_;
  for (int s : set_) in_set_[static_cast<std::size_t>(row_of(s))] = 0;
  set_.clear();
  for (int s : cand_) push(s);  // dependent or repeated rows are skipped
  // Dual feasibility: the most negative multiplier leaves, one at a time.
  for (;;) {
    solve_set(lo, hi);
    const int leave = most_negative(lo, hi);
    if (leave < 0) break;
    if (steps_++ >= max_steps) return false;
    remove(leave);
  }
  // Goldfarb-Idnani: the most violated row p joins through partial steps that keep
  // every multiplier of its sign (a row whose multiplier reaches zero leaves).
  for (;;) {
    if (!zc_.allFinite() || !ya_.head(static_cast<Eigen::Index>(set_.size())).allFinite()) return false;
    int join = most_violated(lo, hi, feas_tol);
    if (join == 0 && !az_direct_) {  // confirmed on A z formed directly
      Az_.noalias() = At_.transpose() * zc_;
      az_direct_ = true;
      join = most_violated(lo, hi, feas_tol);
    }
    if (join == 0) break;  // a KKT point
    const int p = row_of(join);
    const double sp = join > 0 ? 1.0 : -1.0;  // oriented row n_p = sp a_p, n_p'z <= sp b_p
    const double bp = join > 0 ? hi(p) : lo(p);
    for (;;) {
      if (steps_++ >= max_steps) return false;
      const int k = static_cast<int>(set_.size());
      // Direction: H dz + A_a' dy + n_p = 0, A_a dz = 0.
      for (int j = 0; j < k; ++j) w_(j) = sp * At_.col(row_of(set_[static_cast<std::size_t>(j)])).dot(W_.col(p));
      L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(w_.head(k));
      L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(w_.head(k));  // -dy
      dz_ = -sp * W_.col(p);
      for (int j = 0; j < k; ++j) dz_.noalias() += w_(j) * W_.col(row_of(set_[static_cast<std::size_t>(j)]));
      const double curvature = -sp * At_.col(p).dot(dz_);  // -n_p'dz >= 0
      const double gap = sp * (At_.col(p).dot(zc_) - bp);  // violation left
      const double t_full = curvature > 1e-9 * W_.col(p).dot(At_.col(p)) ? gap / curvature : HUGE_VAL;  // as push()
      double t_dual = HUGE_VAL;
      int block = -1;
      for (int j = 0; j < k; ++j) {
        const int s = set_[static_cast<std::size_t>(j)];
        if (lo(row_of(s)) == hi(row_of(s))) continue;
        const double mu = s > 0 ? ya_(j) : -ya_(j), dmu = s > 0 ? -w_(j) : w_(j);
        if (dmu < 0.0 && std::max(mu, 0.0) / -dmu < t_dual) {
          t_dual = std::max(mu, 0.0) / -dmu;
          block = j;
        }
      }
      if (t_full == HUGE_VAL && block < 0) {  // p depends on the set and no multiplier gives way
        infeasible_ = certify(p, sp, lo, hi);
        return false;
      }
      const double t = std::min(t_full, t_dual);
      zc_ += t * dz_;
      ya_.head(k) -= t * w_.head(k);
      if (t_full <= t_dual) {  // p joins: its point is the new set's solution
        if (!push(join)) return false;
        solve_set(lo, hi);
        break;
      }
      drop(block);
    }
  }
  if (most_negative(lo, hi) >= 0) return false;
  z = zc_;
  y.setZero();
  for (std::size_t j = 0; j < set_.size(); ++j) y(row_of(set_[j])) = ya_(static_cast<Eigen::Index>(j));
  return true;
}

}  // namespace tmpc::detail
