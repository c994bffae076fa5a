// Noise-adaptive gain of the offset-free law's Kalman filter (tube_controller.hpp; README
// "Noisy sensors"). The steady-state gain is optimal for the measurement noise R it was
// designed for; louder sensors (a worn IMU, vibration, a GNSS fix degrading) want a
// gain that trusts the measurements less, or the noise reaches the servos. The noise
// monitor (noise_monitor.hpp) already estimates the level s of the noise against the
// design's by covariance matching of residuals (Mehra, IEEE TAC 17, 1972): this keeps
// the steady-state gains for R s^2 (the same Q), s = 1, 2, 4, 8,
//   L_s = P_s C' (C P_s C' + s^2 R)^-1,  P_s the DARE's a-priori covariance for s^2 R,
// computed once at construction, and flies the one whose s is nearest the level (on a
// log scale: the switch from s_j to s_j+1 at sqrt(s_j s_j+1) (1 + kHysteresis), back
// below it over (1 + kHysteresis)). Below the design's noise the design gain stays. Any
// gain is a consistent observer, so a switch moves the estimate by no jump; only its
// noise and speed change. No allocation in update().
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/synthesis/estimator.hpp"

namespace tmpc {

class FilterGainSchedule {
 public:
  static constexpr double kHysteresis = 0.1;
  /// The noise scales s of the gains, the design's (1) first.
  static const std::vector<double>& scales();
  /// k: the designed filter (its model, Q, R and gain L, which is the s = 1 gain).
  /// Throws std::runtime_error when a scaled DARE has no stabilizing solution.
  explicit FilterGainSchedule(const KalmanDesign& k);
  /// The monitor's level (noise / design noise); returns the gain to fly.
  const Eigen::MatrixXd& update(double level);
  const Eigen::MatrixXd& gain() const { return designs_[static_cast<std::size_t>(index_)].L; }
  double scale() const { return scales()[static_cast<std::size_t>(index_)]; }
  /// Which gain flies: an index into scales().
  std::size_t index() const { return static_cast<std::size_t>(index_); }
  /// The filter designed for scales()[i] times the design's noise (its P, R and L).
  const KalmanDesign& design(std::size_t i) const { return designs_[i]; }
  /// The steady innovation's standard deviations under the noise of the gain flown.
  const Eigen::VectorXd& innovation_sd() const { return sds_[static_cast<std::size_t>(index_)]; }
  /// Back to the design's gain.
  void reset() { index_ = 0; }

 private:
  std::vector<KalmanDesign> designs_;
  std::vector<Eigen::VectorXd> sds_;
  int index_ = 0;
};

}  // namespace tmpc
