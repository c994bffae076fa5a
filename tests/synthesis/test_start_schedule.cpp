// The filter's start schedule: start_gains() on a measurement map that selects states
// and on one that does not, and the schedules shared between controllers
// (start_schedule.hpp).
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "tmpc/synthesis/estimator.hpp"
#include "tmpc/synthesis/start_schedule.hpp"

namespace tmpc {
namespace {

constexpr double T = 0.05;

/// A mass on a line with a force on it, its position and speed measured.
KalmanDesign mass_filter() {
  const Eigen::Matrix2d A = (Eigen::Matrix2d() << 1, T, 0, 1).finished();
  const Eigen::Vector2d B(0.5 * T * T, T);
  return design_kalman(A, B, B, Eigen::MatrixXd(2, 0), {0, 1}, Eigen::Vector3d(1e-6, 1e-6, 1e-4).asDiagonal(),
                       Eigen::Vector2d(1e-4, 4e-4).asDiagonal());
}

// Oracle: measuring 2 y instead of y (C and the noise's deviation doubled) is the same
// filter, its gains halved. The doubled C selects nothing, so start_gains takes its
// general products there and its indexing on the selecting C.
TEST(StartSchedule, AMeasurementMapThatSelectsNothingGivesTheSameFilter) {
  const KalmanDesign k = mass_filter();
  KalmanDesign k2 = k;
  k2.C = 2.0 * k.C;
  k2.R = 4.0 * k.R;
  k2.L = 0.5 * k.L;
  const Eigen::MatrixXd P0 = start_covariance(k, 1, 2.0, 0.0, 0.5);
  std::vector<Eigen::VectorXd> sd, sd2;
  const std::vector<Eigen::MatrixXd> g = start_gains(k, P0, 1e-3, 2000, &sd);
  const std::vector<Eigen::MatrixXd> g2 = start_gains(k2, P0, 1e-3, 2000, &sd2);
  ASSERT_GT(g.size(), 5u);
  ASSERT_EQ(g2.size(), g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_LT((2.0 * g2[i] - g[i]).cwiseAbs().maxCoeff(), 1e-12 * g[i].cwiseAbs().maxCoeff()) << "step " << i;
    EXPECT_LT((sd2[i] - 2.0 * sd[i]).cwiseAbs().maxCoeff(), 1e-12 * sd[i].maxCoeff()) << "step " << i;
  }
}

TEST(StartSchedule, EqualInputsShareOneScheduleAndItIsStartGains) {
  const KalmanDesign k = mass_filter();
  const Eigen::MatrixXd P0 = start_covariance(k, 1, 2.0, 0.0, 0.5);
  const std::shared_ptr<const StartSchedule> a = shared_start_schedule(k, P0);
  const std::shared_ptr<const StartSchedule> b = shared_start_schedule(mass_filter(), P0);  // an equal copy
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a.get(), b.get());
  std::vector<Eigen::VectorXd> sd;
  const std::vector<Eigen::MatrixXd> g = start_gains(k, P0, 1e-3, 2000, &sd);
  ASSERT_EQ(a->gains.size(), g.size());
  ASSERT_EQ(a->innovation_sds.size(), sd.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(a->gains[i], g[i]);
    EXPECT_EQ(a->innovation_sds[i], sd[i]);
  }
  // Any input changed is another schedule: the prior, the tolerance, the filter.
  Eigen::MatrixXd P1 = P0;
  P1(2, 2) = std::nextafter(P1(2, 2), 10.0);
  EXPECT_NE(shared_start_schedule(k, P1).get(), a.get());
  EXPECT_NE(shared_start_schedule(k, P0, 1e-2).get(), a.get());
  EXPECT_NE(shared_start_schedule(k, P0, 1e-3, 10).get(), a.get());
  KalmanDesign noisier = k;
  noisier.R *= 2.0;
  EXPECT_NE(shared_start_schedule(noisier, P0).get(), a.get());
  // Bounded: past kStartScheduleCache other schedules the first is computed again.
  for (int i = 0; i < kStartScheduleCache; ++i) shared_start_schedule(k, P0, 1e-3, 100 + i);
  const std::shared_ptr<const StartSchedule> again = shared_start_schedule(k, P0);
  EXPECT_NE(again.get(), a.get());
  EXPECT_EQ(again->gains.size(), g.size());
}

TEST(StartSchedule, ControllersBuiltAtOnceOnThreadsGetOneEqualSchedule) {
  const KalmanDesign k = mass_filter();
  const Eigen::MatrixXd P0 = start_covariance(k, 1, 3.0, 0.0, 0.5);
  std::vector<std::shared_ptr<const StartSchedule>> got(4);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i) threads.emplace_back([&, i] { got[i] = shared_start_schedule(k, P0); });
  for (std::thread& t : threads) t.join();
  const std::vector<Eigen::MatrixXd> g = start_gains(k, P0);
  for (const auto& s : got) {
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(s->gains.size(), g.size());
    EXPECT_EQ(s->gains.back(), g.back());
  }
  EXPECT_EQ(shared_start_schedule(k, P0).get(), got.front().get());  // the first stored is kept
}

}  // namespace
}  // namespace tmpc
