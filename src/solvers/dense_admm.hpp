// Internal: the exact ADMM machinery (E3) for  min 1/2 x'Hx + f'x  s.t.  lo <= A x <= hi,
// shared by the polytope ("admm") and constrained-zonotope ("cz") solvers.
//
// Splitting with a copy z = A x on which the bounds act (OSQP-like); every sub-step
// is exact:
//   x~ = (H + sigma I + A' R A)^-1 (sigma x - f + A'(R z^ - y^))       (factored once)
//   y_1/2 = y^ + r R (A x~ - z^)                                         (4.21)
//   z = clip(A x~ + R^-1 y_1/2, lo, hi)
//   y = y_1/2 + s R (A x~ - z)                                           (4.23)
// R = diag(rho), rho x1e3 on equality rows. Nesterov (4.29)-(4.31) on (z, y) with the
// residual restart of Algorithm 4.2: c = ||R^-1 (y - y^)|| + ||A'R (z - z^)||.
// Stop (OSQP): ||A x - z||_inf <= eps_abs + eps_rel max(||Ax||, ||z||) and
// ||H x + f + A'y||_inf <= eps_abs + eps_rel max(||Hx||, ||A'y||, ||f||), in the
// original units. The problem is equilibrated once (Ruiz, 15 passes on [H A'; A 0]
// plus a cost scaling) and solved in scaled coordinates x~ = D^-1 x, z~ = E z,
// y~ = c E^-1 y. At every termination check the active set read from (z, y) is
// polished (option `polish`), the result accepted only if it is a KKT point: with H
// positive definite by a dual active-set finish from that guess (Goldfarb-Idnani on
// the Schur complement, schur_active_set.hpp), which ends most solves at the first
// check and cuts ADMM's slow tail; for the CZ form (H singular) by the dense
// equality-constrained solve once the residuals are within 100x the tolerance. An
// infeasible instance ends with status Infeasible on OSQP's certificate (eps_pinf).
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "active_set_polish.hpp"
#include "schur_active_set.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc::detail {

/// Segments shifted by one block for the warm start: [offset, offset + count*block).
struct ShiftSegment {
  int offset, block, count;
};

class DenseAdmm {
 public:
  DenseAdmm(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, const Eigen::VectorXd& lo0, const Eigen::VectorXd& hi0,
            const SolverOptions& opt, std::vector<ShiftSegment> x_shift, std::vector<ShiftSegment> row_shift);

  /// Solve with the given f, lo, hi (preallocated by the caller); result into `res`.
  void solve(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, SolveResult& res);
  void reset() { have_previous_ = false; }
  double rho() const { return rho_; }

 private:
  void factor();
  /// OSQP-style polish: guess the active set from (z, y), finish it exactly (Schur
  /// active-set steps, or the dense KKT solve when H is singular, then only when
  /// `near`: the residuals within the polish band); true (and x_, y_, z_ replaced)
  /// when that gives a KKT point of the scaled problem.
  bool try_polish(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, bool near);
  static void shift(Eigen::VectorXd& v, const std::vector<ShiftSegment>& segs);
  /// The Schur finish (up to polish_steps steps) of the rows proposed to schur_; true
  /// (and x_, y_, z_ replaced) when that gives a KKT point.
  bool finish(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  /// Solve the guessed active set in polish_ (the Schur finish, or the dense KKT solve
  /// with up to polish_refine steps); true (and x_, y_, z_ replaced) on a KKT point.
  bool solve_guess(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  /// x_, y_ from the polished point (xp_, yp_), z_ = clip(A x_).
  void accept(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  /// OSQP's primal infeasibility certificate on dy = y - y(previous check):
  /// ||A'dy|| <= eps ||dy|| and hi'max(dy, 0) + lo'min(dy, 0) <= -eps ||dy|| (inf-norms).
  bool primal_infeasible(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  /// Crash start: the active set of the start point (cold: the unconstrained
  /// minimizer) polished with active-set steps; true when that is the KKT point.
  bool crash(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, bool warm);

  Eigen::MatrixXd H_, A_, K_;        // scaled: H~ = c D H D, A~ = E A D (Ruiz)
  Eigen::VectorXd D_, E_;             // variable and constraint scalings
  double c_ = 1.0;                    // cost scaling
  Eigen::LLT<Eigen::MatrixXd> llt_;  // K
  Eigen::VectorXd rho_vec_, rho_inv_;
  std::vector<char> equality_;
  SolverOptions opt_;
  double rho_ = 0.0, rho0_ = 0.0;
  std::vector<ShiftSegment> x_shift_, row_shift_;
  bool have_previous_ = false;
  // Workspace and memory (warm start).
  Eigen::VectorXd x_, z_, y_, zh_, yh_, zprev_, yprev_, xt_, zt_, yhalf_, rhs_, tmp_n_, tmp_m_, Ax_, Hx_, Aty_;
  Eigen::VectorXd y_check_, dy_;      // y at the previous termination check, its change (infeasibility)
  Eigen::VectorXd fs_, los_, his_;    // scaled instance
  ActiveSetPolish polish_;            // the active-set guess (and its dense KKT solve: CZ)
  SchurActiveSet schur_;              // its Schur-complement finish (H positive definite)
  std::vector<std::pair<double, int>> order_;  // the guess by strength |y| (capacity m)
  std::vector<int> guess_;            // the guess, signed rows (+(i+1) upper, -(i+1) lower)
  std::vector<int> seen_;             // the guess at the previous check
  std::vector<int> tried_guess_;      // the last guess that failed
  bool tried_ = false;                // a guess was tried in this solve
  int finish_steps_ = 0;              // active-set steps of the Schur finish in this solve
  Eigen::VectorXd xp_, yp_;
};

}  // namespace tmpc::detail
