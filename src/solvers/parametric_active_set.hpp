// "active-set": the exact dual active-set solver of the parametric QP (parametric_qp.hpp)
//   min 1/2 z'Hz + (f0 + F theta)'z   s.t.   lo0 <= A z + E theta <= hi0,
// everything that does not depend on theta computed once (the parametric form):
//   u(theta) = u0 + K theta     the unconstrained minimizer -H^-1 (f0 + F theta)
//   v(theta) = c0 + C theta     the rows' values A u + E theta there (C = A K + E)
//   G = A H^-1 A', W = H^-1 A'  the rows' coupling through the Hessian
// For an active set S (signed rows at their bounds b_S, multipliers y: + upper, - lower)
// the KKT point is  G_SS y_S = v_S - b_S,  z = u - W_:S y_S,  row values s = v - G_:S y_S:
// the bounds are constant and only k = |S| columns of G are touched. Online: v from one
// product (first in single precision with a rigorous rounding bound; in double only when
// a row is within that bound of its bounds or out of them); no row out of its bounds
// means z = u (the mission's usual QP); otherwise
// Goldfarb-Idnani steps (Math. Prog. 27, 1983, the dual method of DAQP, Arnstrom et al.
// 2022) from S = {} or from the previous period's set made dual feasible: the most
// violated row joins through partial steps that keep every multiplier of its sign; a
// row that cannot join (dependent, no multiplier gives way) ends the solve with a
// verified certificate of primal infeasibility (Farkas: A'r = 0, support < 0).
// Rows certified redundant over the parameter's domain at design time
// (redundant_rows.hpp, recorded in the artifact) are left out while theta is in that
// domain; outside it every row is kept. G_SS is kept as a Cholesky factor grown a row
// at a time and rebuilt after a removal (k <= nz). No allocation after set-up. Ends with
// max-iterations after max_iterations steps, time-budget past time_budget_us.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc::detail {

class ParametricActiveSet final : public QpSolver {
 public:
  /// `redundant`: rows of qp left out while theta is in `domain` (empty: none).
  ParametricActiveSet(const ParametricQp& qp, const std::vector<int>& redundant, const ParameterDomain& domain,
                      const SolverOptions& opt);
  const SolveResult& solve(const Eigen::VectorXd& theta) override;
  void reset() override { warm_.clear(); }
  const char* name() const override { return "active-set"; }
  const ParametricQp& problem() const override { return qp_; }
  const SolverOptions& options() const override { return opt_; }
  /// Rows the solver works on while theta is in the domain (qp rows less the redundant).
  int kept_rows() const { return static_cast<int>(reduced_.rows.size()); }
  /// The last solve used the reduced rows (theta in the domain).
  bool used_reduced() const { return used_reduced_; }

 private:
  /// One set of rows with its parametric data (the reduced set or all rows).
  struct Rows {
    std::vector<int> rows;   // original row of each
    std::vector<int> index;  // original row -> position here (-1: absent)
    Eigen::MatrixXd C, G, W, At;
    Eigen::VectorXd c0, lo, hi, v, s;
    Eigen::MatrixXf Cf;        // C in single precision (the screening product)
    Eigen::VectorXf vf;
    Eigen::VectorXd row_l1;    // ||C_r||_1 (the screening's rounding bound)
    std::vector<char> in_set;
    void build(const ParametricQp& qp, const Eigen::MatrixXd& K, const Eigen::VectorXd& u0, const Eigen::MatrixXd& Hinv,
               const std::vector<int>& keep);
  };
  /// Appends a signed row (+(r+1) upper, -(r+1) lower) with multiplier y to the set
  /// and the factor; false when it depends on the set or the set is full.
  bool push(Rows& R, int signed_row, double y);
  void refactor(Rows& R);
  void remove(Rows& R, int j);
  /// y_S and s for the current set, from scratch.
  void solve_set(Rows& R);
  int most_violated(const Rows& R) const;
  int most_negative(const Rows& R) const;
  bool certify(const Rows& R, int p, double sigma);
  double bound(const Rows& R, int s) const { return s > 0 ? R.hi(s - 1) : R.lo(-s - 1); }
  static int row_of(int s) { return (s > 0 ? s : -s) - 1; }
  /// Goldfarb-Idnani from the current set; the status of the solve.
  SolveStatus run(Rows& R);

  ParametricQp qp_;
  SolverOptions opt_;
  ParameterDomain domain_;
  std::vector<int> unit_rows_;             // domain rows on one parameter: its index
  std::vector<double> unit_lo_, unit_hi_;  // and bounds
  Eigen::MatrixXd Dg_;                     // the other domain rows (leading columns)
  Eigen::VectorXd dg_lo_, dg_hi_;
  int nz_ = 0, np_ = 0;
  Eigen::MatrixXd K_, Hinv_;
  Eigen::VectorXd u0_, u_, dtheta_, f_, Hz_, ray_;
  Eigen::VectorXf thf_;
  Rows reduced_, full_;
  Rows* last_ = nullptr;                // the rows of the last solve (their in_set marks)
  bool has_reduced_ = false, used_reduced_ = false;
  Eigen::MatrixXd L_;                   // Cholesky factor of G_SS (nz x nz capacity)
  Eigen::VectorXd ya_, w_, dy_, tmp_;   // multipliers of the set, workspaces
  std::vector<int> set_, rebuild_, warm_;
  std::vector<double> rebuild_y_;
  int steps_ = 0;
  double t0_ = 0.0;  // start of the solve (us)
  double feas_tol_ = 1e-10;
  SolveResult res_;
};

}  // namespace tmpc::detail
