// Yawing into a force on the load: a reference governor for missions whose yaw is free.
// The rod tilts under a steady horizontal force F on the load by about
// atan(|F| / (m_L g)), split between the load's phi and theta by the yaw; the box bounds
// each, so the tilt held is largest with F along the box's diagonal in the load's yaw
// frame (tan(beta) = phi bound / theta bound). When the force's larger component at
// the mission's yaw would tilt the rod past `tilt_on` of its bound, the governor turns
// the reference's yaw toward the diagonal nearest the mission's yaw, rate- and
// acceleration-limited (the offset's rate added to the mission's stays within the
// any-yaw envelope's, where the design's model holds); below 0.8 of that it returns to
// the mission's yaw. Its input is the controller's force estimate (the offset-free
// observer's d_hat, in the reference's yaw frame). The box's yaw row then bounds the
// error from the governed reference, the mission's yaw is not followed.
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

#include "tmpc/model/trajectory.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct YawGovernorSettings {
  double rate_max = 0.0;             ///< rad/s of the offset
  double acceleration_max = 0.2;     ///< rad/s^2 of the offset
  double force_on = 0.0;             ///< N: the larger horizontal component that turns it
  double phi_bound = 0.5, theta_bound = 0.5;  ///< rad: the box's half-widths
};

/// The settings for flying `t` for `duration` s with artifact `a`: the box's phi and
/// theta bounds, force_on from tilt_on (a fraction of the smaller bound) and the load's
/// weight, the rate left by the trajectory's own yaw rate under the envelope's. Throws
/// std::invalid_argument for a design that is not an any-yaw tiltrotor design or a
/// trajectory that leaves the offset no rate.
YawGovernorSettings yaw_governor_settings(const ControllerArtifact& a, const Trajectory& t, double duration,
                                          double tilt_on = 0.3);

class YawGovernor {
 public:
  explicit YawGovernor(YawGovernorSettings s);
  /// After a period: the force estimate `d_frame` (x, y in the frame turned by
  /// `psi_frame` from the world's: the reference's yaw minus the design's) and the
  /// mission's yaw move the offset one period `dt`. No allocation.
  void update(const Eigen::Vector2d& d_frame, double psi_frame, double psi_mission, double dt);
  void reset();
  double offset() const { return offset_; }
  double rate() const { return rate_; }
  double acceleration() const { return acc_; }
  double target() const { return target_; }
  bool active() const { return active_; }

 private:
  YawGovernorSettings s_;
  double offset_ = 0.0, rate_ = 0.0, acc_ = 0.0, target_ = 0.0;
  bool active_ = false;
};

/// The trajectory with its yaw (rate, acceleration) plus a governor's offset.
class GovernedTrajectory : public Trajectory {
 public:
  GovernedTrajectory(std::shared_ptr<const Trajectory> base, const YawGovernor* g);
  TrajectoryPoint at(double t) const override;
  double duration() const override { return base_->duration(); }
  std::string description() const override { return base_->description() + ", yaw into the force"; }

 private:
  std::shared_ptr<const Trajectory> base_;
  const YawGovernor* g_;
};

}  // namespace tmpc
