// The error state of the tube controller, thesis (5.5)-(5.7): x_tilde = (q - q_r,
// q' - q_r', integrals of the x, y, z, psi errors), psi wrapped to (-pi, pi].
#pragma once

#include <string>

#include <Eigen/Core>

#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/reference.hpp"

namespace tmpc {

/// Name of error state i: the coordinate ("x", "gamma_1"), its rate ("d_x"), or an
/// integral ("int_x", "int_psi").
std::string error_state_name(int i);

class TrackingError {
 public:
  TrackingError() : xt_(Eigen::VectorXd::Zero(24)) {}
  /// x_tilde at the measured state x (q, q') and the reference point r; no allocation.
  const Eigen::VectorXd& update(const State20& x, const ReferencePoint& r);
  /// The measured part of x_tilde (q - q_r, q' - q_r', psi wrapped; 20 entries) into
  /// `e` (sized 20), without touching the integrals. No allocation.
  static void measured(const State20& x, const ReferencePoint& r, Eigen::VectorXd& e);
  /// After the period: integrate the x, y, z, psi errors over dt (rectangle rule, 5.7).
  void integrate(double dt);
  void reset() { integral_.setZero(); xt_.setZero(); }
  const Eigen::VectorXd& value() const { return xt_; }

 private:
  Eigen::VectorXd xt_;
  Eigen::Vector4d integral_ = Eigen::Vector4d::Zero();
};

}  // namespace tmpc
