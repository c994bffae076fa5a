// The nominal QP as a function of the nominal state x0 (thesis (4.7)):
//   min 1/2 z'H z + (f0 + F x0)'z   s.t.   lo0 - E x0 <= A z <= hi0 - E x0
// with z = u_hat. For the polytope formulation A = [I; P], E = [0; Q]. Rows with
// lo = hi are equalities. Instances are formed without allocation (bounds_into).
// In the offset-free form the parameter x0 is (x_bar - x_s, d_hat) and E = [Q Tx-stack;
// Tu-stack] on its two parts (mpc_qp.hpp); nx() counts both. The input-rate weight's
// v_prev (mpc_qp.hpp) is the parameter's last m entries: in F only (E's columns zero).
// Softened form (MpcQpData::soft()): z = (u_hat, s) with one slack s_i >= 0 per state,
// shared by the N stages, and the exact L1 penalty (Fletcher's l1QP):
//   min 1/2 u'H u + f'u + rho 1's + eps/2 s's
//   s.t. U_bar (inputs, hard);  x_k,i - s_i <= hi_k,i;  x_k,i + s_i >= lo_k,i;  s >= 0
// rows: M m inputs, N n upper, N n lower (one-sided: the other bound infinite), n slacks.
// eps = 1e-6 of H's largest diagonal (kSlackCurvature) keeps the Hessian positive
// definite; the quadratic term's gradient vanishes at s = 0, so it does not change
// exactness (no slack while the hard QP is feasible and rho covers its multipliers).
// Its size: 1e-8 left the slack directions so flat (the softened Hessian's condition
// number 1e8) that the dual active set cycled on a gust's QP (4000 steps); a large eps
// weighs large slacks quadratically and the 0.24 s horizon spends the inputs on the
// immediate violation: at H's smallest eigenvalue (7e-5 of its largest diagonal here)
// the sustained 3 N flight diverges. 1e-7 to 3e-6 fly both (README "soft constraints").
#pragma once

#include <Eigen/Core>

#include "tmpc/qp/mpc_qp.hpp"

namespace tmpc {

/// The softened form's slack curvature eps, relative to H's largest diagonal (above).
inline constexpr double kSlackCurvature = 1e-6;

struct ParametricQp {
  Eigen::MatrixXd H, F, A, E;
  Eigen::VectorXd f0, lo0, hi0;
  int slacks = 0;  ///< softened form: the last `slacks` entries of z (0: hard)
  int nz() const { return static_cast<int>(H.rows()); }
  int nc() const { return static_cast<int>(A.rows()); }
  int nx() const { return static_cast<int>(F.cols()); }

  /// The MPC data's QP (softened when d.soft()).
  static ParametricQp from_mpc(const MpcQpData& d);
  /// The softened form of a hard MPC QP whose last N n rows are the state constraints
  /// (see above). Throws std::invalid_argument for a non-positive penalty or sizes.
  static ParametricQp soften(const ParametricQp& hard, int N, int n, double penalty);
  /// f = f0 + F x0, lo = lo0 - E x0, hi = hi0 - E x0 into preallocated vectors.
  void instance_into(const Eigen::VectorXd& x0, Eigen::VectorXd& f, Eigen::VectorXd& lo, Eigen::VectorXd& hi) const;
  CondensedQp instance(const Eigen::VectorXd& x0) const;
};

}  // namespace tmpc
