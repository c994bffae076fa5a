// KKT residuals of  min 1/2 z'Hz + f'z  s.t.  lo <= A z <= hi  at (z, y), with the
// multiplier convention y_i > 0 on an active upper bound, y_i < 0 on an active lower
// bound (y_i free on an equality row):
//   stationarity      ||H z + f + A'y||_inf
//   primal            max(lo - A z, A z - hi, 0)
//   complementarity   max_i |y_i^+ (hi_i - a_i'z)|, |y_i^- (a_i'z - lo_i)|
//   dual sign         the multiplier mass on bounds that are not there (infinite)
// Written once here from the definition; the solvers never call it.
#pragma once

#include <Eigen/Core>

#include "tmpc/qp/mpc_qp.hpp"

namespace tmpc {

struct KktResiduals {
  double stationarity = 0.0;
  double primal = 0.0;
  double complementarity = 0.0;
  double dual_sign = 0.0;
  double max() const;
};

KktResiduals kkt_residuals(const CondensedQp& qp, const Eigen::VectorXd& z, const Eigen::VectorXd& y);

/// Multipliers for a primal point alone: least squares on the rows within `tol` of a
/// bound, with the sign fixed by the bound (for solvers without inequality duals).
Eigen::VectorXd estimate_multipliers(const CondensedQp& qp, const Eigen::VectorXd& z, double tol);

double qp_objective(const CondensedQp& qp, const Eigen::VectorXd& z);

}  // namespace tmpc
