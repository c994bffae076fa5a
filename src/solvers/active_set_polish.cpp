// Active-set polish (see active_set_polish.hpp).
#include "active_set_polish.hpp"

#include <algorithm>
#include <cmath>

namespace tmpc::detail {

ActiveSetPolish::ActiveSetPolish(int nz, int nc) : nz_(nz), zc_(Eigen::VectorXd::Zero(nz)), Az_(Eigen::VectorXd::Zero(nc)) {
  for (std::vector<int>* v : {&idx_, &keep_idx_}) v->reserve(static_cast<std::size_t>(nz));
  for (std::vector<double>* v : {&sign_, &keep_sign_}) v->reserve(static_cast<std::size_t>(nz));
}

bool ActiveSetPolish::add(int row, bool upper) {
  if (static_cast<int>(idx_.size()) >= nz_) return false;
  idx_.push_back(row);
  sign_.push_back(upper ? 1.0 : -1.0);
  return true;
}

bool ActiveSetPolish::solve(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, const Eigen::VectorXd& f,
                            const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double feas_tol, Eigen::VectorXd& z,
                            Eigen::VectorXd& y) {
  const int k = size();
  const int size = nz_ + k;
  have_point_ = false;
  if (size > 128) return false;
  kkt_.setZero(size, size);
  rhs_.resize(size);
  kkt_.topLeftCorner(nz_, nz_) = H;
  auto fill_rhs = [&]() {
    rhs_.head(nz_) = -f;
    for (int j = 0; j < k; ++j) {
      const int i = idx_[static_cast<std::size_t>(j)];
      rhs_(nz_ + j) = sign_[static_cast<std::size_t>(j)] > 0 ? hi(i) : lo(i);
    }
  };
  for (int j = 0; j < k; ++j) {
    const int i = idx_[static_cast<std::size_t>(j)];
    kkt_.block(nz_ + j, 0, 1, nz_) = A.row(i);
    kkt_.block(0, nz_ + j, nz_, 1) = A.row(i).transpose();
  }
  fill_rhs();
  lu_.compute(kkt_);
  sol_ = lu_.solve(rhs_);
  for (int pass = 0; pass < 2; ++pass) {  // iterative refinement (nearly dependent rows)
    rhs_.noalias() -= kkt_ * sol_;
    sol_ += lu_.solve(rhs_);
    fill_rhs();
  }
  if (!sol_.allFinite()) return false;
  zc_ = sol_.head(nz_);
  Az_.noalias() = A * zc_;
  have_point_ = true;
  const double ymax = k > 0 ? sol_.tail(k).cwiseAbs().maxCoeff() : 0.0;
  for (int j = 0; j < k; ++j) {
    if (sol_(nz_ + j) * sign_[static_cast<std::size_t>(j)] < -1e-10 * std::max(1.0, ymax)) return false;
  }
  for (Eigen::Index i = 0; i < Az_.size(); ++i) {
    if (Az_(i) > hi(i) + feas_tol || Az_(i) < lo(i) - feas_tol) return false;
  }
  z = zc_;
  y.setZero();
  for (int j = 0; j < k; ++j) y(idx_[static_cast<std::size_t>(j)]) = sol_(nz_ + j);
  return true;
}

bool ActiveSetPolish::refine(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double feas_tol) {
  if (!have_point_) return false;
  const int k = size();
  const double ymax = k > 0 ? sol_.tail(k).cwiseAbs().maxCoeff() : 0.0;
  keep_idx_.clear();
  keep_sign_.clear();
  for (int j = 0; j < k; ++j) {  // keep the rows whose multipliers have their bound's sign
    if (sol_(nz_ + j) * sign_[static_cast<std::size_t>(j)] >= -1e-10 * std::max(1.0, ymax)) {
      keep_idx_.push_back(idx_[static_cast<std::size_t>(j)]);
      keep_sign_.push_back(sign_[static_cast<std::size_t>(j)]);
    }
  }
  bool changed = static_cast<int>(keep_idx_.size()) != k;
  idx_.swap(keep_idx_);
  sign_.swap(keep_sign_);
  // Violated rows join, the most violated first, while there is room.
  while (static_cast<int>(idx_.size()) < nz_) {
    Eigen::Index worst = -1;
    double worst_v = feas_tol;
    for (Eigen::Index i = 0; i < Az_.size(); ++i) {
      const double v = std::max(Az_(i) - hi(i), lo(i) - Az_(i));
      if (v > worst_v && std::find(idx_.begin(), idx_.end(), static_cast<int>(i)) == idx_.end()) {
        worst_v = v;
        worst = i;
      }
    }
    if (worst < 0) break;
    idx_.push_back(static_cast<int>(worst));
    sign_.push_back(Az_(worst) > hi(worst) ? 1.0 : -1.0);
    Az_(worst) = Az_(worst) > hi(worst) ? hi(worst) : lo(worst);  // counted once
    changed = true;
  }
  have_point_ = false;
  return changed;
}

}  // namespace tmpc::detail
