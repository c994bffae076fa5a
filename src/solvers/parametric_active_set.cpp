// The parametric dual active-set solver (see parametric_active_set.hpp).
#include "parametric_active_set.hpp"
#include "solve_clock.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "solvers_internal.hpp"

namespace tmpc::detail {

namespace {
constexpr double kDependent = 1e-10;  // Schur pivot below this fraction of G_pp: p depends on the set
}  // namespace

void ParametricActiveSet::Rows::build(const ParametricQp& qp, const Eigen::MatrixXd& K, const Eigen::VectorXd& u0,
                                      const Eigen::MatrixXd& Hinv, const std::vector<int>& keep) {
  rows = keep;
  index.assign(static_cast<std::size_t>(qp.nc()), -1);
  const Eigen::Index m = static_cast<Eigen::Index>(keep.size());
  Eigen::MatrixXd A(m, qp.nz()), E(m, qp.nx());
  lo.resize(m);
  hi.resize(m);
  for (Eigen::Index r = 0; r < m; ++r) {
    const int i = keep[static_cast<std::size_t>(r)];
    index[static_cast<std::size_t>(i)] = static_cast<int>(r);
    A.row(r) = qp.A.row(i);
    E.row(r) = qp.E.row(i);
    lo(r) = qp.lo0(i);
    hi(r) = qp.hi0(i);
  }
  C = A * K + E;
  c0 = A * u0;
  Cf = C.cast<float>();
  row_l1 = C.cwiseAbs().rowwise().sum();
  vf.setZero(m);
  At = A.transpose();
  W = Hinv * At;
  G = A * W;
  v.setZero(m);
  s.setZero(m);
  in_set.assign(static_cast<std::size_t>(m), 0);
}

ParametricActiveSet::ParametricActiveSet(const ParametricQp& qp, const std::vector<int>& redundant,
                                         const ParameterDomain& domain, const SolverOptions& opt)
    : qp_(qp), opt_(opt), domain_(domain) {
  nz_ = qp.nz();
  np_ = qp.nx();
  const Eigen::LLT<Eigen::MatrixXd> llt(qp.H);
  if (nz_ == 0 || llt.info() != Eigen::Success) {
    throw std::invalid_argument("solver 'active-set': the Hessian is not positive definite");
  }
  Hinv_ = llt.solve(Eigen::MatrixXd::Identity(nz_, nz_));
  K_ = -Hinv_ * qp.F;
  u0_ = -Hinv_ * qp.f0;
  std::vector<int> all(static_cast<std::size_t>(qp.nc()));
  for (int i = 0; i < qp.nc(); ++i) all[static_cast<std::size_t>(i)] = i;
  full_.build(qp, K_, u0_, Hinv_, all);
  if (!redundant.empty()) {
    if (domain.D.cols() != np_ || domain.lo.size() != domain.D.rows() || domain.hi.size() != domain.D.rows()) {
      throw std::invalid_argument("solver 'active-set': the redundant rows' parameter domain has " +
                                  std::to_string(domain.D.cols()) + " columns for " + std::to_string(np_) + " parameters");
    }
    std::vector<char> drop(static_cast<std::size_t>(qp.nc()), 0);
    for (int i : redundant) {
      if (i < 0 || i >= qp.nc()) {
        throw std::invalid_argument("solver 'active-set': redundant row " + std::to_string(i) + " of a QP with " +
                                    std::to_string(qp.nc()) + " rows");
      }
      drop[static_cast<std::size_t>(i)] = 1;
    }
    std::vector<int> keep;
    for (int i = 0; i < qp.nc(); ++i) {
      if (!drop[static_cast<std::size_t>(i)]) keep.push_back(i);
    }
    reduced_.build(qp, K_, u0_, Hinv_, keep);
    has_reduced_ = true;
    // Rows bounding one parameter are compared directly; the others form a product over
    // the columns up to their last nonzero one.
    std::vector<int> general;
    for (Eigen::Index i = 0; i < domain.D.rows(); ++i) {
      Eigen::Index j = 0;
      const bool unit = (domain.D.row(i).array() != 0.0).count() == 1 && domain.D.row(i).cwiseAbs().maxCoeff(&j) == 1.0 &&
                        domain.D(i, j) == 1.0;
      if (unit) {
        unit_rows_.push_back(static_cast<int>(j));
        unit_lo_.push_back(domain.lo(i));
        unit_hi_.push_back(domain.hi(i));
      } else {
        general.push_back(static_cast<int>(i));
      }
    }
    Eigen::Index cols = 0;
    for (int i : general) {
      for (Eigen::Index j = 0; j < np_; ++j) {
        if (domain.D(i, j) != 0.0) cols = std::max(cols, j + 1);
      }
    }
    Dg_.resize(static_cast<Eigen::Index>(general.size()), cols);
    dg_lo_.resize(Dg_.rows());
    dg_hi_.resize(Dg_.rows());
    for (Eigen::Index r = 0; r < Dg_.rows(); ++r) {
      Dg_.row(r) = domain.D.row(general[static_cast<std::size_t>(r)]).head(cols);
      dg_lo_(r) = domain.lo(general[static_cast<std::size_t>(r)]);
      dg_hi_(r) = domain.hi(general[static_cast<std::size_t>(r)]);
    }
    dtheta_.setZero(Dg_.rows());
  }
  u_.setZero(nz_);
  thf_.setZero(np_);
  f_.setZero(nz_);
  Hz_.setZero(nz_);
  ray_.setZero(nz_);
  L_.setZero(nz_, nz_);
  ya_.setZero(nz_);
  w_.setZero(nz_);
  dy_.setZero(nz_);
  tmp_.setZero(nz_);
  for (std::vector<int>* v : {&set_, &rebuild_, &warm_}) v->reserve(static_cast<std::size_t>(nz_));
  rebuild_y_.reserve(static_cast<std::size_t>(nz_));
  res_.z.setZero(nz_);
  res_.y.setZero(qp.nc());
}

bool ParametricActiveSet::push(Rows& R, int s, double y) {
  const int r = row_of(s);
  const int k = static_cast<int>(set_.size());
  if (R.in_set[static_cast<std::size_t>(r)] || k >= nz_) return false;
  for (int l = 0; l < k; ++l) w_(l) = R.G(row_of(set_[static_cast<std::size_t>(l)]), r);
  L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(w_.head(k));
  const double g = R.G(r, r);
  const double d = g - w_.head(k).squaredNorm();
  if (!(d > kDependent * g)) return false;  // dependent on the set (or a zero row)
  L_.row(k).head(k) = w_.head(k).transpose();
  L_(k, k) = std::sqrt(d);
  set_.push_back(s);
  ya_(k) = y;
  R.in_set[static_cast<std::size_t>(r)] = 1;
  return true;
}

void ParametricActiveSet::refactor(Rows& R) {
  rebuild_.assign(set_.begin(), set_.end());
  rebuild_y_.clear();
  for (std::size_t j = 0; j < set_.size(); ++j) rebuild_y_.push_back(ya_(static_cast<Eigen::Index>(j)));
  for (int s : set_) R.in_set[static_cast<std::size_t>(row_of(s))] = 0;
  set_.clear();
  for (std::size_t j = 0; j < rebuild_.size(); ++j) push(R, rebuild_[j], rebuild_y_[j]);
}

void ParametricActiveSet::remove(Rows& R, int j) {
  const int k = static_cast<int>(set_.size());
  R.in_set[static_cast<std::size_t>(row_of(set_[static_cast<std::size_t>(j)]))] = 0;
  set_.erase(set_.begin() + j);
  for (int l = j; l + 1 < k; ++l) ya_(l) = ya_(l + 1);
  refactor(R);  // a subset of independent rows stays independent
}

void ParametricActiveSet::solve_set(Rows& R) {
  const int k = static_cast<int>(set_.size());
  for (int j = 0; j < k; ++j) ya_(j) = R.v(row_of(set_[static_cast<std::size_t>(j)])) - bound(R, set_[static_cast<std::size_t>(j)]);
  L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(ya_.head(k));
  L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(ya_.head(k));
  R.s = R.v;
  for (int j = 0; j < k; ++j) R.s.noalias() -= ya_(j) * R.G.col(row_of(set_[static_cast<std::size_t>(j)]));
}

int ParametricActiveSet::most_violated(const Rows& R) const {
  int join = 0;
  double worst = 0.0;
  const Eigen::Index m = R.s.size();
  for (Eigen::Index r = 0; r < m; ++r) {
    const double s = R.s(r);
    const double up = s - R.hi(r), dn = R.lo(r) - s;
    if (up <= worst && dn <= worst) continue;
    if (R.in_set[static_cast<std::size_t>(r)]) continue;
    if (up > worst && up > feas_tol_ * (1.0 + std::abs(R.hi(r)))) {
      worst = up;
      join = static_cast<int>(r) + 1;
    } else if (dn > worst && dn > feas_tol_ * (1.0 + std::abs(R.lo(r)))) {
      worst = dn;
      join = -(static_cast<int>(r) + 1);
    }
  }
  return join;
}

int ParametricActiveSet::most_negative(const Rows& R) const {
  const int k = static_cast<int>(set_.size());
  const double ymax = k > 0 ? ya_.head(k).cwiseAbs().maxCoeff() : 0.0;
  int leave = -1;
  double worst = -1e-12 * std::max(1.0, ymax);
  for (int j = 0; j < k; ++j) {
    const int s = set_[static_cast<std::size_t>(j)];
    const int r = row_of(s);
    if (R.lo(r) == R.hi(r)) continue;  // an equality row's multiplier has either sign
    const double mu = s > 0 ? ya_(j) : -ya_(j);
    if (mu < worst) {
      worst = mu;
      leave = j;
    }
  }
  return leave;
}

bool ParametricActiveSet::certify(const Rows& R, int p, double sigma) {
  // The ray r = (dy on the set, sigma on p): A'r = 0 and, with A'r = 0,
  // r'(bound - E theta) = r'(bound - v) = sum_{r_i > 0} r_i (hi_i - v_i) + sum_{r_i < 0} r_i (lo_i - v_i) < 0
  // (OSQP's test, inf-norms, 1e-6).
  const int k = static_cast<int>(set_.size());
  ray_ = sigma * R.At.col(p);
  double norm = 1.0;
  double support = sigma * ((sigma > 0 ? R.hi(p) : R.lo(p)) - R.v(p));
  for (int j = 0; j < k; ++j) {
    const int r = row_of(set_[static_cast<std::size_t>(j)]);
    const double d = dy_(j);
    ray_.noalias() += d * R.At.col(r);
    norm = std::max(norm, std::abs(d));
    support += d * ((d > 0.0 ? R.hi(r) : R.lo(r)) - R.v(r));
  }
  return ray_.cwiseAbs().maxCoeff() <= 1e-6 * norm && support <= -1e-6 * norm;
}

SolveStatus ParametricActiveSet::run(Rows& R) {
  const int budget = opt_.max_iterations;
  // The time budget (the runtime's deadline) is read at every step: a step costs about 1 us.
  auto late = [this] { return opt_.time_budget_us > 0.0 && now_us() - t0_ > opt_.time_budget_us; };
  // Warm start: the previous set, made dual feasible (the most negative multiplier leaves).
  if (!set_.empty()) {
    for (;;) {
      solve_set(R);
      const int leave = most_negative(R);
      if (leave < 0) break;
      if (steps_++ >= budget) return SolveStatus::MaxIterations;
      if (late()) return SolveStatus::TimeBudget;
      remove(R, leave);
    }
  }
  for (int confirm = 0;;) {
    int join = most_violated(R);
    if (join == 0) {
      // Confirm on the set's point solved from scratch (the steps update s and y in place).
      if (set_.empty() || confirm++ > 0) return SolveStatus::Converged;
      solve_set(R);
      if (most_negative(R) >= 0) return SolveStatus::NumericalFailure;
      join = most_violated(R);
      if (join == 0) return SolveStatus::Converged;
    }
    confirm = 0;
    const int p = row_of(join);
    const double sigma = join > 0 ? 1.0 : -1.0;
    const double bp = join > 0 ? R.hi(p) : R.lo(p);
    double yp = 0.0;
    for (;;) {
      if (steps_++ >= budget) return SolveStatus::MaxIterations;
      if (late()) return SolveStatus::TimeBudget;
      const int k = static_cast<int>(set_.size());
      // dy = -sigma G_SS^-1 G_Sp: the set's multipliers per unit of p's.
      for (int j = 0; j < k; ++j) dy_(j) = -sigma * R.G(row_of(set_[static_cast<std::size_t>(j)]), p);
      L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(dy_.head(k));
      L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(dy_.head(k));
      double curvature = R.G(p, p);  // d = G_pp - G_pS G_SS^-1 G_Sp = G_pp + sigma G_pS dy
      for (int j = 0; j < k; ++j) curvature += sigma * R.G(p, row_of(set_[static_cast<std::size_t>(j)])) * dy_(j);
      // p's value from the multipliers (s is brought up to date only when p joins:
      // a step that drops a row needs no other row's value).
      double sp = R.v(p) - R.G(p, p) * yp;
      for (int j = 0; j < k; ++j) sp -= R.G(p, row_of(set_[static_cast<std::size_t>(j)])) * ya_(j);
      const double gap = sigma * (sp - bp);
      const double t_full = curvature > kDependent * R.G(p, p) ? gap / curvature : HUGE_VAL;
      double t_dual = HUGE_VAL;
      int block = -1;
      for (int j = 0; j < k; ++j) {
        const int s = set_[static_cast<std::size_t>(j)];
        if (R.lo(row_of(s)) == R.hi(row_of(s))) continue;
        const double mu = s > 0 ? ya_(j) : -ya_(j), dmu = s > 0 ? dy_(j) : -dy_(j);
        if (dmu < 0.0 && std::max(mu, 0.0) / -dmu < t_dual) {
          t_dual = std::max(mu, 0.0) / -dmu;
          block = j;
        }
      }
      if (t_full == HUGE_VAL && block < 0) {  // p depends on the set and no multiplier gives way
        return certify(R, p, sigma) ? SolveStatus::Infeasible : SolveStatus::NumericalFailure;
      }
      const double t = std::min(t_full, t_dual);
      // y_S += t dy; p's multiplier += sigma t.
      ya_.head(k) += t * dy_.head(k);
      yp += sigma * t;
      if (t_full <= t_dual) {
        if (!push(R, join, yp)) return SolveStatus::NumericalFailure;
        // Every row's value at the new point: s = v - G_:S y_S.
        R.s = R.v;
        for (int j = 0; j <= k; ++j) R.s.noalias() -= ya_(j) * R.G.col(row_of(set_[static_cast<std::size_t>(j)]));
        break;
      }
      remove(R, block);
    }
  }
}

const SolveResult& ParametricActiveSet::solve(const Eigen::VectorXd& theta) {
  if (!valid_state(theta, np_, res_)) return res_;
  t0_ = now_us();
  // The rows: the reduced set while theta is in the certificate's domain.
  bool in_domain = false;
  if (has_reduced_) {
    in_domain = true;
    for (std::size_t i = 0; in_domain && i < unit_rows_.size(); ++i) {
      const double t = theta(unit_rows_[i]);
      in_domain = t <= unit_hi_[i] && t >= unit_lo_[i];
    }
    if (in_domain && Dg_.rows() > 0) {
      dtheta_.noalias() = Dg_ * theta.head(Dg_.cols());
      in_domain = (dtheta_.array() <= dg_hi_.array()).all() && (dtheta_.array() >= dg_lo_.array()).all();
    }
  }
  Rows& R = in_domain ? reduced_ : full_;
  used_reduced_ = in_domain;
  u_ = u0_;
  u_.noalias() += K_ * theta;
  if (last_ != nullptr) {
    for (int s : set_) last_->in_set[static_cast<std::size_t>(row_of(s))] = 0;
  }
  last_ = &R;
  set_.clear();
  steps_ = 0;
  // The usual case first, in single precision: C theta in float (half the bytes of the
  // largest product) with the rounding bound |fl(C theta) - C theta| <=
  // gamma ||C_r||_1 ||theta||_inf, gamma = (np + 4) 2^-24 (the entries' and theta's
  // rounding, the products, any order of summation). Every row inside its bounds by more
  // than that: u is feasible, hence the optimum, and exact (u is computed in double).
  const double theta_max = theta.cwiseAbs().maxCoeff();
  bool screened = theta_max < 1e30;  // far from float's range
  if (screened) {
    thf_ = theta.cast<float>();
    R.vf.noalias() = R.Cf * thf_;
    const double gamma = (np_ + 4) * 0x1p-24 * 1.01;
    for (Eigen::Index r = 0; r < R.vf.size(); ++r) {
      const double v = R.c0(r) + static_cast<double>(R.vf(r));
      const double e = gamma * R.row_l1(r) * theta_max + 1e-30;
      if (!(v + e <= R.hi(r) && v - e >= R.lo(r))) {
        screened = false;
        break;
      }
    }
  }
  if (!screened) {
    R.v = R.c0;
    R.v.noalias() += R.C * theta;
    R.s = R.v;
  }
  if (!screened && opt_.warm_start) {
    for (int s : warm_) {
      const int r = R.index[static_cast<std::size_t>(row_of(s))];
      if (r >= 0) push(R, s > 0 ? r + 1 : -(r + 1), 0.0);
    }
  }
  res_.status = screened ? SolveStatus::Converged : run(R);
  // The solution: z = u - W_:S y_S, multipliers in the original rows.
  const int k = static_cast<int>(set_.size());
  res_.z = u_;
  res_.y.setZero();
  warm_.clear();
  for (int j = 0; j < k; ++j) res_.z.noalias() -= ya_(j) * R.W.col(row_of(set_[static_cast<std::size_t>(j)]));
  if (res_.status == SolveStatus::Converged && k > 0) {
    // One refinement on the active rows' residual formed from z itself
    // (A_S z + E_S theta - b_S = A_S (z - u) + v_S - b_S): G_SS's conditioning costs the
    // multipliers' products a few digits, which complementarity (y times the row's gap) sees.
    ray_ = res_.z - u_;
    for (int j = 0; j < k; ++j) {
      const int s = set_[static_cast<std::size_t>(j)];
      w_(j) = R.At.col(row_of(s)).dot(ray_) + R.v(row_of(s)) - bound(R, s);
    }
    L_.topLeftCorner(k, k).triangularView<Eigen::Lower>().solveInPlace(w_.head(k));
    L_.topLeftCorner(k, k).transpose().triangularView<Eigen::Upper>().solveInPlace(w_.head(k));
    ya_.head(k) += w_.head(k);
    for (int j = 0; j < k; ++j) res_.z.noalias() -= w_(j) * R.W.col(row_of(set_[static_cast<std::size_t>(j)]));
  }
  for (int j = 0; j < k; ++j) {
    const int s = set_[static_cast<std::size_t>(j)];
    const int r = row_of(s);
    const int orig = R.rows[static_cast<std::size_t>(r)];
    res_.y(orig) = ya_(j);
    warm_.push_back(s > 0 ? orig + 1 : -(orig + 1));
  }
  if (res_.status != SolveStatus::Converged) warm_.clear();
  // Residuals from scratch: the rows' violation (this set of rows) and H z + f + A_S' y_S.
  double viol = 0.0;  // screened: every row proven inside its bounds
  for (Eigen::Index r = 0; !screened && r < R.s.size(); ++r) viol = std::max({viol, R.s(r) - R.hi(r), R.lo(r) - R.s(r)});
  f_ = qp_.f0;
  f_.noalias() += qp_.F * theta;
  Hz_.noalias() = qp_.H * res_.z;
  res_.objective = 0.5 * res_.z.dot(Hz_) + f_.dot(res_.z);
  Hz_ += f_;
  for (int j = 0; j < k; ++j) Hz_.noalias() += ya_(j) * R.At.col(row_of(set_[static_cast<std::size_t>(j)]));
  res_.primal_residual = viol;
  res_.dual_residual = Hz_.cwiseAbs().maxCoeff();
  res_.iterations = steps_;
  res_.active_set_steps = steps_;
  res_.restarts = 0;
  res_.solve_us = now_us() - t0_;
  return res_;
}

}  // namespace tmpc::detail
