// Internal: an active-set finish for  min 1/2 z'Hz + f'z  s.t.  lo <= A z <= hi  with
// H positive definite, on the Schur complement of the KKT system:
//   (A_a H^-1 A_a') y_a = A_a u - b_a,   z = u - (H^-1 A_a') y_a,   u = -H^-1 f,
// from W = H^-1 A' computed once; S = A_a H^-1 A_a' is kept as a Cholesky factor L
// grown a row at a time, so a row dependent on the set (pivot below 1e-9 of its
// diagonal) is never taken and S stays nonsingular.
//
// Start from a guess ordered strongest first (the exact ADMM's multipliers); drop the
// most negative multiplier one row at a time until every multiplier has its bound's
// sign (a dual feasible start); then Goldfarb-Idnani steps (Math. Prog. 27, 1983): the
// most violated row joins through partial steps that keep every multiplier of its
// sign, a row whose multiplier reaches zero leaving, until the point is a KKT point
// (every row within feas_tol, confirmed on A z formed directly) or max_steps. A wrong
// guess of ADMM's early iterates (spurious rows with nonzero multipliers, rows
// dependent on the true set) is what this repairs; the plain polish
// (active_set_polish.hpp) rejects it. A step costs O(k^2 n + k m) with G = A H^-1 A'
// kept (up to 20 MB, else O(k^2 n + m n)); no heap use; at most 128 rows in the set.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace tmpc::detail {

class SchurActiveSet {
 public:
  /// Precomputes H^-1, W = H^-1 A', A' and, when it has at most g_limit entries,
  /// G = A H^-1 A'; false (and unusable) when H is not positive definite (the CZ
  /// formulation).
  bool setup(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, Eigen::Index g_limit = 2'500'000);
  bool ready() const { return ready_; }
  /// The unconstrained minimizer -H^-1 f into z (preallocated).
  void unconstrained(const Eigen::VectorXd& f, Eigen::VectorXd& z) const {
    z.noalias() = Hinv_ * f;
    z *= -1.0;
  }
  /// A new guess: clear, then propose rows in order of confidence.
  void clear() {
    cand_.clear();
    infeasible_ = false;
  }
  void propose(int row, bool upper) {
    if (cand_.size() < cand_.capacity()) cand_.push_back(upper ? row + 1 : -(row + 1));
  }
  /// True with (z, y) the KKT point (y: + upper, - lower, 0 inactive); on failure z
  /// and y are untouched.
  bool solve(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double feas_tol,
             int max_steps, Eigen::VectorXd& z, Eigen::VectorXd& y);
  /// Steps the last solve made.
  int steps() const { return steps_; }
  /// The last solve failed on a verified certificate of primal infeasibility: a ray
  /// dy of multipliers with A'dy = 0 and a negative support of the bounds (OSQP's
  /// test at 1e-6), found when a violated row depends on the set and no multiplier
  /// gives way (Goldfarb-Idnani's infeasibility exit).
  bool infeasible() const { return infeasible_; }

 private:
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 128, 128>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 128, 1>;
  /// Appends row (signed: +(i+1) upper, -(i+1) lower) to the set and L; false when
  /// it depends on the set or the set is full.
  bool push(int signed_row);
  /// Refactors L after removing position j.
  void remove(int j);
  /// Builds and checks the dual ray for joining row p (see infeasible()).
  bool certify(int p, double sp, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  /// Removes position j from the set and from ya_.
  void drop(int j);
  /// The position of the most negative multiplier (relative to the largest), or -1.
  int most_negative(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) const;
  /// The most violated row outside the set (signed as in push), or 0.
  int most_violated(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, double feas_tol) const;
  /// (zc_, ya_, Az_) for the current set, with one refinement on the active rows.
  void solve_set(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  double bound(int j, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) const {
    const int s = set_[static_cast<std::size_t>(j)];
    return s > 0 ? hi(s - 1) : lo(-s - 1);
  }
  static int row_of(int s) { return (s > 0 ? s : -s) - 1; }

  bool ready_ = false;
  int nz_ = 0;
  Eigen::MatrixXd Hinv_, W_, At_;  // H^-1, H^-1 A', A' (its columns: the rows of A)
  Eigen::MatrixXd G_;              // A H^-1 A' (empty for large m)
  Eigen::VectorXd u_, Au_, zc_, Az_, dz_;
  bool az_direct_ = false;         // Az_ formed as A zc_ (not updated through G)
  Small L_;                        // Cholesky factor of S over set_
  SmallVec ya_, rhs_, w_;
  std::vector<int> cand_, set_, rebuild_;
  std::vector<char> in_set_;
  int steps_ = 0;
  bool infeasible_ = false;
};

}  // namespace tmpc::detail
