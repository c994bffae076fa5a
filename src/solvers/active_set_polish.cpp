// Active-set polish (see active_set_polish.hpp).
#include "active_set_polish.hpp"

#include <algorithm>
#include <cmath>

namespace tmpc::detail {

ActiveSetPolish::ActiveSetPolish(int nz, int nc) : nz_(nz), zc_(Eigen::VectorXd::Zero(nz)), Az_(Eigen::VectorXd::Zero(nc)) {
  idx_.reserve(static_cast<std::size_t>(nz));
  sign_.reserve(static_cast<std::size_t>(nz));
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
  const double ymax = k > 0 ? sol_.tail(k).cwiseAbs().maxCoeff() : 0.0;
  for (int j = 0; j < k; ++j) {
    if (sol_(nz_ + j) * sign_[static_cast<std::size_t>(j)] < -1e-10 * std::max(1.0, ymax)) return false;
  }
  zc_ = sol_.head(nz_);
  Az_.noalias() = A * zc_;
  for (Eigen::Index i = 0; i < Az_.size(); ++i) {
    if (Az_(i) > hi(i) + feas_tol || Az_(i) < lo(i) - feas_tol) return false;
  }
  z = zc_;
  y.setZero();
  for (int j = 0; j < k; ++j) y(idx_[static_cast<std::size_t>(j)]) = sol_(nz_ + j);
  return true;
}

}  // namespace tmpc::detail
