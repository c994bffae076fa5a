// Euler-Lagrange model of the tiltrotor with suspended load, thesis (5.1)-(5.3):
//   M(q) q'' + C(q, q') q' + G(q) = L_in(q) u - L_fr q' + L_ab d
// built from the kinematic tree (model spec section 5):
//   M = sum_k m_k Jv_k' Jv_k + Jw_k' I_k Jw_k            (world-frame I_k)
//   C q' = sum_k m_k Jv_k' (Jv_k' q') + Jw_k' (I_k (Jw_k' q') + w_k x I_k w_k)
//          (Newton-Euler projection; J-dot q' from a dual number along q')
//   G = g sum_k m_k (row z of Jv_k)'
//   L_in = [Jv(piv_R)' n_R + lR k Jw_R' n_R, Jv(piv_L)' n_L + lL k Jw_L' n_L, e_aR, e_aL]
// The Christoffel-symbol matrix C(q, q') is also available (for M-dot - 2C skew).
#pragma once

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {

using Vec10 = Eigen::Matrix<double, kNq, 1>;
using Mat10 = Eigen::Matrix<double, kNq, kNq>;
using State20 = Eigen::Matrix<double, kNx, 1>;
using InputMat = Eigen::Matrix<double, kNq, kNu>;

/// M, C q', G and L_in at one (q, q').
template <class T>
struct DynamicsTerms {
  Eigen::Matrix<T, kNq, kNq> M;
  Eigen::Matrix<T, kNq, 1> c;  ///< C(q, q') q'
  Eigen::Matrix<T, kNq, 1> G;
  Eigen::Matrix<T, kNq, kNu> L_in;
};

/// Linearization of x' = f(x, u, d) (thesis (5.5)): A = df/dx, B = df/du, D = df/dd.
struct Linearization {
  Eigen::Matrix<double, kNx, kNx> A;
  Eigen::Matrix<double, kNx, kNu> B;
  Eigen::Matrix<double, kNx, kNd> D;
};

class TiltrotorModel {
 public:
  explicit TiltrotorModel(const VehicleParams& params);

  const VehicleParams& params() const { return params_; }
  const KinematicTree& tree() const { return tree_; }

  Mat10 mass_matrix(const Vec10& q) const;
  Vec10 gravity_vector(const Vec10& q) const;
  InputMat input_matrix(const Vec10& q) const;
  /// C(q, q') q' by the Newton-Euler projection.
  Vec10 coriolis_vector(const Vec10& q, const Vec10& qd) const;
  /// C(q, q') from Christoffel symbols of the first kind (derivatives of M by AD).
  Mat10 coriolis_matrix(const Vec10& q, const Vec10& qd) const;
  /// L_fr (diagonal viscous friction).
  Mat10 friction_matrix() const;
  /// L_ab = [I3; 0]: the disturbance is a force on the load in inertial axes.
  Eigen::Matrix<double, kNq, kNd> disturbance_matrix() const;

  /// Generalized force of a force F (inertial axes) on the main body at its centre of
  /// mass: Jv_body(q)' F.
  Vec10 body_force(const Vec10& q, const Eigen::Vector3d& F) const;
  /// q'' from (5.2).
  Vec10 acceleration(const Vec10& q, const Vec10& qd, const Eigen::Vector4d& u, const Eigen::Vector3d& d) const;
  /// x' = f(x, u, d) from (5.3), x = (q, q').
  State20 state_derivative(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d) const;
  /// The same with a force also on the main body (inertial axes, at its centre of mass).
  State20 state_derivative(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d_load,
                           const Eigen::Vector3d& f_body) const;
  /// Exact Jacobians of f by forward-mode automatic differentiation.
  Linearization linearize(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d) const;

  double kinetic_energy(const Vec10& q, const Vec10& qd) const;
  double potential_energy(const Vec10& q) const;

  /// All terms for a scalar type (double or dual numbers).
  template <class T>
  DynamicsTerms<T> terms(const T* q, const T* qd) const;
  template <class T>
  Eigen::Matrix<T, kNq, kNq> mass_matrix_t(const T* q) const;
  template <class T>
  Eigen::Matrix<T, kNx, 1> state_derivative_t(const T* x, const T* u, const T* d) const;

 private:
  VehicleParams params_;
  KinematicTree tree_;
};

/// One classical RK4 step of x' = f(x, u, d_load, f_body) over h.
State20 rk4_step(const TiltrotorModel& model, const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d_load,
                 const Eigen::Vector3d& f_body, double h);

}  // namespace tmpc
