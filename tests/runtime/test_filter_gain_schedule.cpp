// The noise-adaptive filter gain (runtime/filter_gain_schedule.hpp). Oracle of the gains:
// the innovations of a steady-state Kalman filter are white exactly when its gain is
// optimal for the noise (Mehra 1972), and the lag-1 innovation covariance of any gain L
// follows from its own error covariance, found by a Lyapunov sum (not the DARE):
//   P = M P M' + A L R L' A' + Q,  M = A (I - L C)         (a-priori error covariance)
//   E[nu(k+1) nu(k)'] = C A (P C' - L (C P C' + R))          (zero iff L is optimal for R)
// On a double integrator with a constant force as its disturbance state.
#include <cmath>

#include <gtest/gtest.h>

#include "tmpc/runtime/filter_gain_schedule.hpp"

namespace tmpc {
namespace {

constexpr double kDt = 0.01;

KalmanDesign filter() {
  Eigen::MatrixXd A(2, 2), B(2, 1), D(2, 1);
  A << 1.0, kDt, 0.0, 1.0;
  B << 0.5 * kDt * kDt, kDt;
  D << 0.5 * kDt * kDt, kDt;  // the force, as an acceleration
  const Eigen::MatrixXd Q = Eigen::Vector3d(1e-8, 1e-6, 1e-4).asDiagonal();
  const Eigen::MatrixXd R = Eigen::Vector2d(0.01 * 0.01, 0.1 * 0.1).asDiagonal();
  return design_kalman(A, B, D, Eigen::MatrixXd::Zero(2, 0), {0, 1}, Q, R);
}

/// |E[nu(k+1) nu(k)']| relative to E[nu nu'] for gain L under noise covariance R.
double innovation_lag(const KalmanDesign& k, const Eigen::MatrixXd& L, const Eigen::MatrixXd& R) {
  const Eigen::Index na = k.A_a.rows();
  const Eigen::MatrixXd M = k.A_a * (Eigen::MatrixXd::Identity(na, na) - L * k.C);
  const Eigen::MatrixXd P = stationary_covariance(M, k.A_a * L * R * L.transpose() * k.A_a.transpose() + k.Q);
  const Eigen::MatrixXd S = k.C * P * k.C.transpose() + R;
  const Eigen::MatrixXd lag = k.C * k.A_a * (P * k.C.transpose() - L * S);
  // Normalized by the innovations' standard deviations: a correlation matrix.
  const Eigen::VectorXd sd = S.diagonal().cwiseSqrt().cwiseInverse();
  return (sd.asDiagonal() * lag * sd.asDiagonal()).cwiseAbs().maxCoeff();
}

/// The a-priori estimation error's total variance (trace P) with gain L under noise R.
double error_variance(const KalmanDesign& k, const Eigen::MatrixXd& L, const Eigen::MatrixXd& R) {
  const Eigen::Index na = k.A_a.rows();
  const Eigen::MatrixXd M = k.A_a * (Eigen::MatrixXd::Identity(na, na) - L * k.C);
  return stationary_covariance(M, k.A_a * L * R * L.transpose() * k.A_a.transpose() + k.Q).trace();
}

TEST(FilterGainSchedule, EachGainIsTheOptimalFilterForItsNoise) {
  const KalmanDesign k = filter();
  FilterGainSchedule g(k);
  ASSERT_EQ(FilterGainSchedule::scales().front(), 1.0);
  EXPECT_EQ((g.gain() - k.L).cwiseAbs().maxCoeff(), 0.0);  // the design's gain at the design's noise
  const Eigen::MatrixXd L1 = g.gain();
  double previous_gain = L1.norm();
  for (double level : {2.0, 4.0, 8.0}) {
    const Eigen::MatrixXd& L = g.update(level);
    ASSERT_EQ(g.scale(), level);
    const Eigen::MatrixXd R = (level * level) * k.R;
    const double optimal = innovation_lag(k, L, R), design = innovation_lag(k, L1, R);
    std::printf("noise x%g: innovation lag-1 correlation %.2e with its gain, %.3f with the design's\n", level, optimal,
                design);
    EXPECT_LT(optimal, 1e-8) << level;
    EXPECT_GT(design, 1e-3) << level;  // the design's gain is not the filter for this noise
    EXPECT_LT(error_variance(k, L, R), error_variance(k, L1, R)) << level;
    EXPECT_LT(L.norm(), previous_gain) << level;  // louder noise: the measurements trusted less
    previous_gain = L.norm();
  }
}

TEST(FilterGainSchedule, TheGainFollowsTheLevelWithHysteresis) {
  FilterGainSchedule g(filter());
  auto scale_at = [&](double level) {
    g.update(level);
    return g.scale();
  };
  // Edges at sqrt(2) = 1.414, sqrt(8) = 2.83, sqrt(32) = 5.66, up at 1.1 times them,
  // down below them over 1.1.
  EXPECT_EQ(scale_at(0.0), 1.0);
  EXPECT_EQ(scale_at(1.05), 1.0);  // the design's noise, as the monitor reads it
  EXPECT_EQ(scale_at(1.50), 1.0);  // below 1.556
  EXPECT_EQ(scale_at(1.60), 2.0);
  EXPECT_EQ(scale_at(1.35), 2.0);  // above 1.286: held
  EXPECT_EQ(scale_at(1.25), 1.0);
  EXPECT_EQ(scale_at(10.0), 8.0);  // several steps at once
  EXPECT_EQ(scale_at(5.50), 8.0);  // above 5.14
  EXPECT_EQ(scale_at(3.00), 4.0);
  EXPECT_EQ(scale_at(100.0), 8.0);  // the loudest gain is the last
  g.reset();
  EXPECT_EQ(g.scale(), 1.0);
}

}  // namespace
}  // namespace tmpc
