// Internal: active-set polish for  min 1/2 z'Hz + f'z  s.t.  lo <= A z <= hi.
// Given a guess of the active rows (and which bound), solve the equality-constrained QP
//   [H  A_a'] [z  ]   [-f ]
//   [A_a  0 ] [y_a] = [b_a]        (two steps of iterative refinement)
// and accept the point only if it is a KKT point: every row within its bounds (tol)
// and every multiplier of the sign of its bound. Static storage, no heap use; at most
// 128 variables plus active rows. Used by the reference solver (exactness) and by
// the exact ADMM of the CZ form, whose H is singular (to finish once the active set
// has settled, as OSQP's polish); with H positive definite the exact ADMM finishes
// through schur_active_set.hpp.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

namespace tmpc::detail {

class ActiveSetPolish {
 public:
  explicit ActiveSetPolish(int nz = 0, int nc = 0);
  void clear() {
    idx_.clear();
    sign_.clear();
  }
  /// Adds a row; false when more rows than variables (LICQ cannot hold).
  bool add(int row, bool upper);
  int size() const { return static_cast<int>(idx_.size()); }
  const std::vector<int>& rows() const { return idx_; }
  const std::vector<double>& signs() const { return sign_; }
  /// On success z and y (multipliers of all rows: + upper, - lower, 0 inactive) hold
  /// the KKT point; on failure they are untouched.
  bool solve(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, const Eigen::VectorXd& f, const Eigen::VectorXd& lo,
             const Eigen::VectorXd& hi, double feas_tol, Eigen::VectorXd& z, Eigen::VectorXd& y);
  /// After a failed solve: the primal-dual active-set step (Hintermueller, Ito and
  /// Kunisch 2002) from its point: rows whose multiplier has the wrong sign leave the
  /// guess, violated rows join it (the most violated first, while rows < variables).
  /// False when the guess does not change (or the last solve produced no point).
  bool refine(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double feas_tol);

 private:
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 128, 128>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 128, 1>;
  int nz_ = 0;
  Small kkt_;
  SmallVec sol_, rhs_;
  Eigen::PartialPivLU<Small> lu_;
  std::vector<int> idx_;
  std::vector<double> sign_;
  Eigen::VectorXd zc_, Az_;
  bool have_point_ = false;  // the last solve produced (z, y_a), KKT or not
  std::vector<int> keep_idx_;
  std::vector<double> keep_sign_;
};

}  // namespace tmpc::detail
