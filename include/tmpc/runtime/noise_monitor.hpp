// Sensor-noise monitor of the switched observer (tube_controller.hpp; README "Noisy
// sensors"): which observer the offset-free law should use, read from the measurements.
//
// The one-step residual of consecutive measurements y = x + v (normalized, the applied
// input u): r(k) = y(k) - A y(k-1) - B u(k-1) = (model mismatch) + v(k) - A v(k-1). Its
// change dr(k) = r(k) - r(k-1) cancels the mismatch's slowly varying part (and any
// constant sensor bias) and keeps the white noise:
//   dr(k) = v(k) - (I + A) v(k-1) + A v(k-2),  cov dr = R + (I + A) R (I + A)' + A R A'
// for v white with covariance R (covariance matching of residuals, Mehra, IEEE TAC 17,
// 1972). It also keeps the mismatch's change, which a swinging load or a sustained force
// makes large and smooth; white noise is told from it by its whiteness: consecutive
// differences of white noise anti-correlate,
//   lag dr = E[dr(k) dr(k-1)'] = -(I + A) R - A R (I + A)',
// those of a smooth signal s correlate (E ~ E[ds^2]). So the monitor's statistic per row
// is dr_i(k) (dr_i(k) - dr_i(k-1)): for white noise its expectation is
// (cov dr)_ii - (lag dr)_ii (10 R_ii for A = I), for a smooth s it is ds(k) times the
// change of ds, whose mean over a swing is zero and whose size is a factor omega T
// below ds^2 (the plain dr_i^2 read a 3 N force's swing as 0.09 of the design's noise,
// which brought the filter in a clean flight). With R the noise the Kalman filter was
// designed for, the monitor takes per period the mean of that statistic over each state
// group's rows (positions, angles, velocities, rates), divided by its expectation; the
// median of each group's last kMedianSamples such values (scaled by E[value] / E[median]
// for white noise of covariance R, found at construction by a fixed-seed simulation:
// the differences correlate consecutive values), averages that over a window (the
// running mean until the window is full, an exponential average of that length after)
// and reports the square root of the largest group's average (0 when it is negative):
// the noise level as a fraction of the design's (1: the design's, 0: clean). A force
// step moves r once, which the statistic sees for one or two periods: the median drops
// that, whatever the step's size (a 1 N step read 0.026 without it, a 2 N one would have
// read the 0.05 that brings the filter), while white noise is in every sample. Isolated
// measurement outliers it drops too: the link's plausibility gates
// (runtime/state_gate.hpp) are for those. The tube controller passes the residuals of
// periods its softened QP or its LQR fallback flew as not valid (tube_controller.hpp):
// past what the hard law holds the inputs jump and the model's mismatch reads like noise.
//
// The switch (hysteresis): the filter at the start; the residual observer once a window
// reads below `residual_below`, the filter again as soon as the level exceeds
// `filter_above` (a few periods of design-level noise do it: the median needs 3). The first window is
// short, kStartSamples statistics (the sensors' first check): a start on the filter
// for a whole window cost a clean start its transient (with masses 30 % off the
// filter's slower force estimate let the vertical speed out for 2.7 s, 140 periods,
// where the residual observer holds it), and a start on the residual observer let
// noisy sensors kick a servo to 5 times its rate bound in the first periods.
// No allocation in update().
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/model/state_layout.hpp"

namespace tmpc {

struct NoiseMonitorSettings {
  double residual_below = 0.0;  ///< noise / design noise below which the residual observer flies (0: never)
  double filter_above = 0.0;    ///< noise / design noise above which the filter flies again (>= residual_below)
  double window_s = 1.0;        ///< averaging window, s
  bool enabled() const { return residual_below > 0.0; }
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

class NoiseMonitor {
 public:
  static constexpr long kStartSamples = 5;  ///< statistics of the first check (6 differences, 8 measurements)
  static constexpr int kMedianSamples = 5;    ///< the median of this many statistics enters the average
  /// A: the error model (normalized, n states, the first p physical); rows: the
  /// measured rows the noise is known for, sigma: its standard deviations there
  /// (normalized), kinds: the n states' kinds; dt: the sample time. Throws
  /// std::invalid_argument on inconsistent sizes.
  NoiseMonitor(const Eigen::MatrixXd& A, const std::vector<int>& rows, const Eigen::VectorXd& sigma,
               const std::vector<StateKind>& kinds, double dt, NoiseMonitorSettings s);

  /// One period: r the one-step residual y(k) - A y(k-1) - B u(k-1) (n entries; the
  /// residual observer's, tube_controller.hpp), `valid` false where there is none (the
  /// first period, a restart, a skipped frame): that, or a non-finite r, restarts the
  /// difference chain and keeps the averages. Returns use_filter().
  bool update(const Eigen::VectorXd& r, bool valid = true);
  /// The noise level, a fraction of the design's (0 before any difference is seen).
  double level() const { return level_; }
  /// Whether the Kalman filter should fly (true at the start).
  bool use_filter() const { return filter_; }
  /// The hand-over to the residual observer happened at the first check, this update.
  bool clean_at_start() const { return clean_at_start_; }
  /// Differences averaged so far.
  long samples() const { return samples_; }
  /// Back to the start: the filter, no samples.
  void reset();

 private:
  /// Per group the mean over its rows of d_i (d_i - d_prev_i) / its white-noise
  /// expectation, d the residual's difference (stored as the next d_prev).
  void group_statistic(const Eigen::VectorXd& r, double (&stat)[4]);
  /// The first difference of a chain: d_prev = r - r_prev on the measured rows.
  void store_difference(const Eigen::VectorXd& r);
  /// The median of group g's last statistics (this one included), bias-corrected.
  double robust(int g, double stat);
  void calibrate(const Eigen::MatrixXd& A, const Eigen::VectorXd& R);
  std::vector<int> rows_, group_;
  Eigen::VectorXd inv_mean_;  ///< 1 / ((cov dr)_ii - (lag dr)_ii) on rows_
  std::vector<int> group_rows_;  ///< rows per group (4 groups)
  NoiseMonitorSettings s_;
  long window_ = 1;
  Eigen::VectorXd r_prev_, d_prev_;
  double mean_[4] = {0, 0, 0, 0};
  double recent_[4][kMedianSamples] = {};
  int recent_count_[4] = {0, 0, 0, 0}, recent_next_[4] = {0, 0, 0, 0};
  double median_scale_[4] = {1, 1, 1, 1};  ///< E[statistic] / E[median] for white noise
  int chain_ = 0;  ///< 1: r_prev_ is the previous period's residual; 2: d_prev_ its difference too
  long samples_ = 0;
  double level_ = 0.0;
  bool filter_ = true;
  bool clean_at_start_ = false;
};

}  // namespace tmpc
