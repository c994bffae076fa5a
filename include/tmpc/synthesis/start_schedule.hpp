// The filter's start schedule shared between controllers: estimator.hpp start_gains()
// (the Riccati recursion L_k = P_k C'(C P_k C' + R)^-1, P_k+1 = A_a P_k+ A_a' + Q from
// an opened prior P_0) computed once per distinct filter and prior in a process.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "tmpc/synthesis/estimator.hpp"

namespace tmpc {

/// The gains L_0, L_1, ... of a start (start_gains()) and each step's innovation
/// standard deviations sqrt(diag(C P_k C' + R)). Immutable once built.
struct StartSchedule {
  std::vector<Eigen::MatrixXd> gains;
  std::vector<Eigen::VectorXd> innovation_sds;
};

/// start_gains(k, P0, tolerance, max_steps) memoised on all its inputs (k's A_a, C, Q,
/// R, L, P0, tolerance, max_steps, compared exactly): controllers built from one
/// artifact (each run of a Monte Carlo campaign, a restarted controller) share one
/// schedule instead of each running its up to 2000 steps (four schedules a controller
/// with step detection). Thread-safe; keeps the last kStartScheduleCache schedules.
/// Throws as start_gains.
inline constexpr int kStartScheduleCache = 8;
std::shared_ptr<const StartSchedule> shared_start_schedule(const KalmanDesign& k, const Eigen::MatrixXd& P0,
                                                           double tolerance = 1e-3, int max_steps = 2000);

}  // namespace tmpc
