// The error state of the tube controller, thesis (5.5)-(5.7): x_tilde = (x - x_r for
// the measured states, yaw differences wrapped to (-pi, pi], then the integrals of the
// configured errors: the tiltrotor's x, y, z, psi), sized by the artifact; with a
// reference join (reference_join.hpp) the positions and velocities relative to the
// joined reference, planned at the first update() after construction or reset(), and
// the integrals of those. In an any-yaw design (EnvelopeSettings::any_yaw) the
// horizontal position and velocity errors are turned into the reference's yaw frame,
// e_h' = Rz(-(psi_r - yaw)) e_h: the dynamics are the same at every yaw (gravity is
// vertical), so the model linearized at `yaw` holds there.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/state_layout.hpp"
#include "tmpc/runtime/reference_join.hpp"

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
  /// Join the reference from the first measured error (disabled settings: no join).
  void set_join(ReferenceJoinSettings s);
  /// Take the horizontal errors in the reference's yaw frame, turned by psi_r - yaw:
  /// x, y and their velocities are the first two position and velocity states; throws
  /// std::invalid_argument when the kinds have no yaw or fewer than two of either.
  void set_yaw_frame(double yaw);
  const ReferenceJoin& join() const { return join_; }
  const Eigen::VectorXd& value() const { return xt_; }
  int measured_states() const { return static_cast<int>(kinds_.size()); }

 private:
  std::vector<StateKind> kinds_;
  std::vector<int> integrated_;
  Eigen::VectorXd xt_, integral_;
  ReferenceJoin join_;
  bool join_pending_ = false;
  bool yaw_frame_ = false;
  double yaw_ = 0.0;
  int yaw_row_ = -1, pos_[2] = {-1, -1}, vel_[2] = {-1, -1};
  double t_ = 0.0;  ///< s since the join's start (integrate()'s steps)
};

}  // namespace tmpc
