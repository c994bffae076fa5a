// Small dense linear programs (the explicit-MPC construction, the QP's redundant rows), solved by
// COIN-OR CLP (Debian coinor-libclp-dev):  min c'x  s.t.  A x <= b,  Aeq x = beq,  lo <= x <= hi.
#pragma once

#include <memory>

#include <Eigen/Core>

class ClpSimplex;

namespace tmpc {

enum class LpStatus { Optimal, Infeasible, Unbounded, Failed };
const char* to_string(LpStatus s);

struct LpResult {
  LpStatus status = LpStatus::Failed;
  double value = 0.0;
  Eigen::VectorXd x;
};

/// Empty Aeq (0 rows) for none; lo/hi may hold +-infinity, b +infinity (a row that binds nothing).
LpResult solve_lp(const Eigen::VectorXd& c, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                  const Eigen::MatrixXd& Aeq, const Eigen::VectorXd& beq, const Eigen::VectorXd& lo,
                  const Eigen::VectorXd& hi);

/// Many LPs over one polyhedron {A x <= b, lo <= x <= hi} with changing objectives:
/// the model is loaded once and each solve starts from the previous optimal basis.
class LpWorkspace {
 public:
  LpWorkspace(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi);
  ~LpWorkspace();
  LpWorkspace(LpWorkspace&&) noexcept;
  LpWorkspace& operator=(LpWorkspace&&) noexcept;
  LpResult minimize(const Eigen::VectorXd& c);
  /// Change b_i (+infinity drops the row).
  void set_rhs(int i, double v);

 private:
  std::unique_ptr<ClpSimplex> model_;
  int n_ = 0;
};

/// The largest common slack t <= cap of {x : lo <= A x <= hi} (every row moved inward by
/// t, +-infinite bounds allowed): > 0 when the set has an interior, < 0 when it is empty,
/// -infinity when the LP fails. The feasibility oracle of the solver tests and benchmarks.
double largest_common_slack(const Eigen::MatrixXd& A, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                            double cap = 1.0);

/// Largest ball {c + r u : |u| <= 1} inside {A x <= b, lo <= x <= hi} (rows of A need not
/// be normalized), r capped at r_max. radius < 0 when the set is empty.
struct ChebyshevBall {
  Eigen::VectorXd center;
  double radius = -1.0;
};
ChebyshevBall chebyshev_ball(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& lo,
                             const Eigen::VectorXd& hi, double r_max = 1e3);

}  // namespace tmpc
