// Small dense linear programs for the explicit-MPC construction, solved by COIN-OR
// CLP (Debian coinor-libclp-dev):  min c'x  s.t.  A x <= b,  Aeq x = beq,  lo <= x <= hi.
#pragma once

#include <Eigen/Core>

namespace tmpc {

enum class LpStatus { Optimal, Infeasible, Unbounded, Failed };
const char* to_string(LpStatus s);

struct LpResult {
  LpStatus status = LpStatus::Failed;
  double value = 0.0;
  Eigen::VectorXd x;
};

/// Empty Aeq (0 rows) for none; lo/hi may hold +-infinity.
LpResult solve_lp(const Eigen::VectorXd& c, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                  const Eigen::MatrixXd& Aeq, const Eigen::VectorXd& beq, const Eigen::VectorXd& lo,
                  const Eigen::VectorXd& hi);

/// Largest ball {c + r u : |u| <= 1} inside {A x <= b, lo <= x <= hi} (rows of A need not
/// be normalized), r capped at r_max. radius < 0 when the set is empty.
struct ChebyshevBall {
  Eigen::VectorXd center;
  double radius = -1.0;
};
ChebyshevBall chebyshev_ball(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& lo,
                             const Eigen::VectorXd& hi, double r_max = 1e3);

}  // namespace tmpc
