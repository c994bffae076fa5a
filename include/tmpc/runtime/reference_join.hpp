// A smooth join from where the vehicle is to its reference (a reference governor fixed
// in advance; Bemporad 1998 and Gilbert-Kolmanovsky give the on-line form): at the law's
// start the position error g0 of the translation-invariant rows is taken up by the
// reference, which returns to the mission's along a minimum-jerk profile:
//   r_j(t) = r(t) + g0 (1 - s(t / T)),  s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5,
// so the law sees e_j = e - g0 (1 - s) and e_j' = e' + g0 s'(t / T) / T. The dynamics
// of the tiltrotor do not change under a translation, so the joined reference is a
// trajectory of the same error model; only its acceleration g0 s'' / T^2 is not in
// the feedforward, a force the offset-free observer reads like any other. T is the
// shortest duration whose peak speed (1.875 |g0| / T) and peak acceleration
// (5.7735 |g0| / T^2) stay within the given limits on every axis. Without it the helix
// started 0.6, 0.5 and 0.4 m off made the hard QP infeasible for 97 periods and the
// softened law flew the load past its speed bound (1.60 times it; scenarios/start_offset.yaml).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace tmpc {

struct ControllerArtifact;

struct ReferenceJoinSettings {
  std::vector<int> position_rows, velocity_rows;  ///< pairs: a position and its velocity (measured rows)
  Eigen::VectorXd speed_limit;     ///< per pair: the join's peak speed (m/s), > 0
  double acceleration_limit = 0.0;  ///< the join's peak acceleration on any axis (m/s^2), > 0
  Eigen::VectorXd dead_zone;       ///< per pair: offsets up to this are left to the law (m)
  bool enabled() const { return !position_rows.empty(); }
};

/// The artifact's join: for the tiltrotor its x, y, z rows with peak speed a quarter of
/// each velocity bound, peak acceleration half the envelope's smallest half-width (the
/// LPV model's range) and a dead zone of 5 % of each position bound (a sensor's noise
/// or bias at the start is the law's); none (disabled) for a linear model, whose
/// positions are not translation invariant.
ReferenceJoinSettings reference_join_settings(const ControllerArtifact& a);

class ReferenceJoin {
 public:
  ReferenceJoin() = default;
  explicit ReferenceJoin(ReferenceJoinSettings s);
  /// Plan from the first measured error (its position rows); inactive when every offset
  /// lies in the dead zone.
  void start(const Eigen::VectorXd& e);
  /// Subtract the joined reference's offset at t (s since start()) from the measured
  /// error e (position and velocity rows); no allocation.
  void apply(double t, Eigen::VectorXd& e) const;
  void stop() { active_ = false; }
  /// Settings with rows to join (start() may still find every offset in the dead zone).
  bool enabled() const { return s_.enabled(); }
  bool active() const { return active_; }
  double duration() const { return T_; }
  const Eigen::VectorXd& offset() const { return g0_; }

 private:
  ReferenceJoinSettings s_;
  Eigen::VectorXd g0_;
  double T_ = 0.0;
  bool active_ = false;
};

}  // namespace tmpc
