// The nominal QP as a function of the nominal state x0 (thesis (4.7)):
//   min 1/2 z'H z + (f0 + F x0)'z   s.t.   lo0 - E x0 <= A z <= hi0 - E x0
// with z = u_hat. For the polytope formulation A = [I; P], E = [0; Q]. Rows with
// lo = hi are equalities. Instances are formed without allocation (bounds_into).
// In the offset-free form the parameter x0 is (x_bar - x_s, d_hat) and E = [Q Tx-stack;
// Tu-stack] on its two parts (mpc_qp.hpp); nx() counts both.
#pragma once

#include <Eigen/Core>

#include "tmpc/qp/mpc_qp.hpp"

namespace tmpc {

struct ParametricQp {
  Eigen::MatrixXd H, F, A, E;
  Eigen::VectorXd f0, lo0, hi0;
  int nz() const { return static_cast<int>(H.rows()); }
  int nc() const { return static_cast<int>(A.rows()); }
  int nx() const { return static_cast<int>(F.cols()); }

  static ParametricQp from_mpc(const MpcQpData& d);
  /// f = f0 + F x0, lo = lo0 - E x0, hi = hi0 - E x0 into preallocated vectors.
  void instance_into(const Eigen::VectorXd& x0, Eigen::VectorXd& f, Eigen::VectorXd& lo, Eigen::VectorXd& hi) const;
  CondensedQp instance(const Eigen::VectorXd& x0) const;
};

}  // namespace tmpc
