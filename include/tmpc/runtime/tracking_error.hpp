// The error state of the tube controller, thesis (5.5)-(5.7): x_tilde = (x - x_r for
// the measured states, yaw differences wrapped to (-pi, pi], then the integrals of the
// configured errors: the tiltrotor's x, y, z, psi), sized by the artifact.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/state_layout.hpp"

namespace tmpc {

class TrackingError {
 public:
  /// `kinds` of the measured states, `integrated` the measured states whose errors
  /// are integrated (appended in that order).
  TrackingError(std::vector<StateKind> kinds, std::vector<int> integrated);
  /// x_tilde at the measured state x and its reference x_r; no allocation.
  const Eigen::VectorXd& update(const Eigen::VectorXd& x, const Eigen::VectorXd& x_r);
  /// The measured part of x_tilde into `e` (sized measured()), without the integrals.
  void measured(const Eigen::VectorXd& x, const Eigen::VectorXd& x_r, Eigen::VectorXd& e) const;
  /// After the period: integrate the configured errors over dt (rectangle rule, 5.7).
  void integrate(double dt);
  void reset();
  const Eigen::VectorXd& value() const { return xt_; }
  int measured_states() const { return static_cast<int>(kinds_.size()); }

 private:
  std::vector<StateKind> kinds_;
  std::vector<int> integrated_;
  Eigen::VectorXd xt_, integral_;
};

}  // namespace tmpc
