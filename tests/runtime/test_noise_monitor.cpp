// The sensor-noise monitor (runtime/noise_monitor.hpp) against the noise injected into
// a simulated plant (the oracle: the known noise level, not the monitor's formula): a
// double integrator per axis, flown by a smooth input, with an unmodelled constant
// acceleration, a force step and a sensor bias, so that the one-step residual is never
// zero even without noise.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "tmpc/runtime/noise_monitor.hpp"

namespace tmpc {
namespace {

constexpr double kDt = 0.01;

struct Plant {
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(4, 4), B = Eigen::MatrixXd::Zero(4, 2);
  Eigen::VectorXd sigma = (Eigen::VectorXd(4) << 0.01, 0.02, 0.1, 0.2).finished();  // design noise
  std::vector<StateKind> kinds{StateKind::Position, StateKind::Position, StateKind::Velocity, StateKind::Velocity};
  Plant() {
    A(0, 2) = A(1, 3) = kDt;
    B(0, 0) = B(1, 1) = 0.5 * kDt * kDt;
    B(2, 0) = B(3, 1) = kDt;
  }
};

/// Flies `periods` periods with noise `scale` times the design's from period `onset`
/// until `stop` (none outside), and returns the monitor's level and choice after each.
struct Flight {
  std::vector<double> level;
  std::vector<bool> filter;
  /// RMS of the first velocity row's residual change over the design noise's (sqrt(6)
  /// sigma: dr = v(k) - 2 v(k-1) + v(k-2) there): what a variance of dr alone would read.
  double dr_rms_ratio = 0.0;
};
/// `swing`: an unmodelled sinusoidal acceleration of that amplitude (m/s^2) at a 0.5 m
/// pendulum's frequency, sqrt(9.81 / 0.5) rad/s: a swinging load's smooth mismatch.
Flight fly(NoiseMonitor& mon, const Plant& p, double scale, long periods, long onset = 0, long stop = 1L << 40,
           unsigned seed = 3, double step = 1.0, double swing = 0.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4), y(4), y_prev(4), u(2), r(4);
  const Eigen::VectorXd bias = (Eigen::VectorXd(4) << 0.05, -0.03, 0.0, 0.0).finished();
  Flight f;
  u.setZero();
  Eigen::VectorXd r_prev = Eigen::VectorXd::Zero(4);
  double dr_sq = 0.0;
  for (long k = 0; k < periods; ++k) {
    y = x + bias;
    if (k >= onset && k < stop) {
      for (int i = 0; i < 4; ++i) y(i) += scale * p.sigma(i) * g(rng);
    }
    // The one-step residual of the measurements (u: the input applied since y_prev).
    if (k > 0) r = y - p.A * y_prev - p.B * u;
    if (k > 1) dr_sq += (r(2) - r_prev(2)) * (r(2) - r_prev(2));
    if (k > 0) r_prev = r;
    f.filter.push_back(mon.update(r, k > 0));
    y_prev = y;
    f.level.push_back(mon.level());
    const double t = static_cast<double>(k) * kDt;
    u << std::sin(0.7 * t), std::cos(0.3 * t);
    // The plant: the model plus an unmodelled constant acceleration and a step at 2 s.
    Eigen::VectorXd a = u + Eigen::Vector2d(0.3, -0.2) + (t >= 2.0 ? Eigen::Vector2d(step, 0.5 * step) : Eigen::Vector2d::Zero());
    a += swing * std::sin(std::sqrt(9.81 / 0.5) * t) * Eigen::Vector2d(1.0, -0.6);
    x = p.A * x + p.B * a;
  }
  f.dr_rms_ratio = std::sqrt(dr_sq / static_cast<double>(std::max(1L, periods - 2))) / (std::sqrt(6.0) * p.sigma(2));
  return f;
}

NoiseMonitorSettings settings(double window_s = 1.0) {
  NoiseMonitorSettings s;
  s.residual_below = 0.025;
  s.filter_above = 0.05;
  s.window_s = window_s;
  return s;
}

TEST(NoiseMonitor, ReadsTheInjectedNoiseLevelAsAFractionOfTheDesigns) {
  const Plant p;
  for (double scale : {1.0, 0.3, 0.1}) {
    NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings(5.0));
    const Flight f = fly(mon, p, scale, 3000);
    // The largest of two groups' estimates over 500 samples: within 12 % of the truth.
    EXPECT_NEAR(f.level.back(), scale, 0.12 * scale) << "noise " << scale << " of the design's";
    EXPECT_TRUE(f.filter.back()) << scale;
  }
}

TEST(NoiseMonitor, CleanSensorsWithBiasModelErrorAndAForceStepReadNearZeroAndHandOverAtTheFirstCheck) {
  const Plant p;
  NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
  const Flight f = fly(mon, p, 0.0, 600);
  for (long k = 0; k < 600; ++k) {
    // The filter until the first check's 5 statistics (6 differences, 8 measurements) read clean.
    EXPECT_EQ(f.filter[static_cast<std::size_t>(k)], k < 7) << k;
    EXPECT_LT(f.level[static_cast<std::size_t>(k)], 0.025) << k;  // the step at 2 s included
  }
}

// A force step moves the residual for one period (two where it starts inside a period):
// the median of 5 drops it, however large (at 1000 times the step, the velocity rows'
// residual jumps by kDt * 1000 = 10, 50 of their dr's design standard deviations: a
// window's plain mean would read several times the design's noise).
TEST(NoiseMonitor, AForceStepOfAnySizeIsNotNoise) {
  const Plant p;
  for (double step : {1.0, 30.0, 1000.0}) {
    NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
    const Flight f = fly(mon, p, 0.0, 400, 0, 1L << 40, 3, step);
    for (long k = 7; k < 400; ++k) {
      EXPECT_FALSE(f.filter[static_cast<std::size_t>(k)]) << "step " << step << " at " << k;
      EXPECT_LT(f.level[static_cast<std::size_t>(k)], 0.025) << "step " << step << " at " << k;
    }
  }
}

// A swinging load (or a sustained force the controller fights) changes the residual
// smoothly: its dr correlates from one period to the next where white noise's
// anti-correlates, and the statistic dr (dr - dr_prev) is a factor omega T smaller for it
// (4.4 rad/s x 10 ms here) and averages to zero over a swing. A variance of dr alone
// reads such a swing as noise: at 300 m/s^2, 0.38 of the design's, 7.7 times filter_above.
TEST(NoiseMonitor, ASmoothSwingReadsATwentiethOfWhatItsVarianceWould) {
  const Plant p;
  for (double swing : {10.0, 100.0, 300.0, 1000.0}) {
    NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
    const Flight f = fly(mon, p, 0.0, 1000, 0, 1L << 40, 3, 1.0, swing);
    const double peak = *std::max_element(f.level.begin() + 7, f.level.end());
    EXPECT_LT(peak, 0.06 * f.dr_rms_ratio) << "swing " << swing << ": dr's variance reads " << f.dr_rms_ratio;
    if (swing <= 300.0) {
      EXPECT_NEAR(f.dr_rms_ratio, 0.00128 * swing, 0.03 * 0.00128 * swing) << swing;  // the variance's reading: 0.38 at 300
      for (long k = 7; k < 1000; ++k) EXPECT_FALSE(f.filter[static_cast<std::size_t>(k)]) << "swing " << swing << " at " << k;
    }
  }
  // Noise under the largest swing reads as noise, not masked by it.
  for (double scale : {1.0, 0.3}) {
    NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings(5.0));
    const Flight f = fly(mon, p, scale, 3000, 0, 1L << 40, 3, 1.0, 1000.0);
    EXPECT_NEAR(f.level.back(), scale, 0.15 * scale) << "noise " << scale << " under the swing";
    for (long k = 0; k < 3000; ++k) EXPECT_TRUE(f.filter[static_cast<std::size_t>(k)]) << scale << " at " << k;
  }
}

TEST(NoiseMonitor, NoisySensorsKeepTheFilterFromTheStartAndAfterTheNoiseItReturnsAfterAWholeWindow) {
  const Plant p;
  for (double scale : {1.0, 0.1}) {
    NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
    const Flight f = fly(mon, p, scale, 400);
    for (long k = 0; k < 400; ++k) EXPECT_TRUE(f.filter[static_cast<std::size_t>(k)]) << scale << " at " << k;
  }
  // Noise that stops: the residual observer again only once the average over the window
  // (an exponential one after the first window) has fallen below residual_below.
  NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
  const Flight f = fly(mon, p, 1.0, 1500, 0, 300);
  long k = 300;
  while (k < 1500 && f.filter[static_cast<std::size_t>(k)]) ++k;
  // From a level near 1 the average falls by (1 - 1/100) a period: below 0.025^2 after ~640.
  EXPECT_GT(k - 300, 500);
  EXPECT_LT(k - 300, 800);
  for (; k < 1500; ++k) EXPECT_FALSE(f.filter[static_cast<std::size_t>(k)]) << k;
}

TEST(NoiseMonitor, NoiseAppearingWhileTheResidualObserverFliesBringsTheFilterBack) {
  const Plant p;
  for (const auto& [scale, within] : {std::pair<double, long>{1.0, 4}, {0.2, 40}}) {
    NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
    const Flight f = fly(mon, p, scale, 600, 300);
    EXPECT_FALSE(f.filter[299]) << scale;  // clean so far: the residual observer
    long back = -1;
    for (long k = 300; k < 600 && back < 0; ++k) {
      if (f.filter[static_cast<std::size_t>(k)]) back = k - 300;
    }
    EXPECT_GE(back, 0) << scale;
    EXPECT_LE(back, within) << "noise " << scale << " of the design's: the filter after " << back << " periods";
    for (long k = 300 + back; k < 600; ++k) EXPECT_TRUE(f.filter[static_cast<std::size_t>(k)]) << k;  // and it stays
  }
}

TEST(NoiseMonitor, ARestartKeepsTheAverageAndBadInputIsNamed) {
  const Plant p;
  NoiseMonitor mon(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, settings());
  fly(mon, p, 1.0, 300);
  const double level = mon.level();
  const long samples = mon.samples();
  Eigen::VectorXd y = Eigen::VectorXd::Constant(4, 100.0);
  mon.update(y, false);  // a restart: no residual
  mon.update(y, true);   // one residual after it: still no difference
  EXPECT_EQ(mon.samples(), samples);
  EXPECT_DOUBLE_EQ(mon.level(), level);
  y(0) = std::nan("");
  mon.update(y, true);
  EXPECT_EQ(mon.samples(), samples);
  EXPECT_TRUE(mon.use_filter());
  mon.reset();
  EXPECT_EQ(mon.samples(), 0);
  EXPECT_TRUE(mon.use_filter());

  auto error = [&](auto&& make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  NoiseMonitorSettings bad = settings();
  bad.filter_above = 0.01;
  EXPECT_NE(error([&] { NoiseMonitor(p.A, {0, 1, 2, 3}, p.sigma, p.kinds, kDt, bad); }).find("filter_above"),
            std::string::npos);
  EXPECT_NE(error([&] { NoiseMonitor(p.A, {0, 1, 2}, p.sigma, p.kinds, kDt, settings()); }).find("4 noise levels for 3"),
            std::string::npos);
  Eigen::VectorXd zero = p.sigma;
  zero(2) = 0.0;
  EXPECT_NE(error([&] { NoiseMonitor(p.A, {0, 1, 2, 3}, zero, p.kinds, kDt, settings()); }).find("row 2 must be positive"),
            std::string::npos);
}

}  // namespace
}  // namespace tmpc
