// Sensor noise: per state group, sample mean = bias and sample deviation = white
// level (statistical oracle, 20,000 draws), nothing on the integral states or on a
// group without noise, and the same seed gives the same sequence.
#include <gtest/gtest.h>

#include <cmath>

#include "tmpc/sim/noise.hpp"

namespace tmpc {
namespace {

TEST(SensorNoise, EachGroupGetsItsBiasAndItsDeviation) {
  NoiseSpec spec;
  spec.white = {0.005, 0.00524, 0.0, 0.033};  // position, angle, velocity, angular rate
  spec.bias = {0.01, 0.0, 0.2, 0.0};
  spec.seed = 4;
  const std::vector<StateKind> kinds = {StateKind::Position, StateKind::Yaw, StateKind::Velocity,
                                        StateKind::AngularRate, StateKind::Integral};
  SensorNoise noise(spec, kinds);
  const int draws = 20000;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(5), sq = sum;
  for (int k = 0; k < draws; ++k) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(5);
    noise.apply(x);
    sum += x;
    sq += x.cwiseProduct(x);
  }
  const Eigen::VectorXd mean = sum / draws;
  const Eigen::VectorXd sd = (sq / draws - mean.cwiseProduct(mean)).cwiseSqrt();
  EXPECT_NEAR(mean(0), 0.01, 4.0 * 0.005 / std::sqrt(draws));  // within 4 standard errors
  EXPECT_NEAR(sd(0), 0.005, 0.03 * 0.005);
  EXPECT_NEAR(mean(1), 0.0, 4.0 * 0.00524 / std::sqrt(draws));  // the yaw is an angle
  EXPECT_NEAR(sd(1), 0.00524, 0.03 * 0.00524);
  EXPECT_NEAR(mean(2), 0.2, 1e-12);  // a bias and no white noise: the bias
  EXPECT_LT(sd(2), 1e-6);
  EXPECT_NEAR(sd(3), 0.033, 0.03 * 0.033);
  EXPECT_EQ(sum(4), 0.0);  // integral states are computed, not measured
}

TEST(SensorNoise, SeededAndValidated) {
  NoiseSpec spec;
  spec.white = {0.01, 0.01, 0.01, 0.01};
  spec.seed = 7;
  const std::vector<StateKind> kinds(6, StateKind::Position);
  SensorNoise a(spec, kinds), b(spec, kinds);
  spec.seed = 8;
  SensorNoise c(spec, kinds);
  Eigen::VectorXd xa = Eigen::VectorXd::Zero(6), xb = xa, xc = xa;
  a.apply(xa);
  b.apply(xb);
  c.apply(xc);
  EXPECT_EQ(xa, xb);
  EXPECT_NE(xa, xc);
  EXPECT_FALSE(NoiseSpec{}.any());
  spec.white[2] = -1.0;
  EXPECT_THROW(SensorNoise(spec, kinds), std::invalid_argument);
}

// Glitches: each sample of a group's rows is off by +-size with the given probability
// (binomial oracle over 200,000 samples: within 4 standard deviations), both signs
// alike; they come from their own generator, so the white noise of a scenario is the
// same sample for sample with glitches added; out-of-range specs are refused.
TEST(SensorNoise, GlitchesComeWithTheirProbabilityOnTheirOwnStream) {
  NoiseSpec clean;
  clean.white = {0.005, 0.0, 0.0, 0.0};
  clean.seed = 4;
  NoiseSpec glitchy = clean;
  glitchy.outlier = {0.3, 0.0, 0.0, 0.0};
  glitchy.outlier_probability = {0.002, 0.5, 0.0, 0.0};  // no size on the angles: nothing there
  const std::vector<StateKind> kinds = {StateKind::Position, StateKind::Angle};
  SensorNoise a(clean, kinds), b(glitchy, kinds);
  const int draws = 200000;
  long up = 0, down = 0;
  for (int k = 0; k < draws; ++k) {
    Eigen::VectorXd xa = Eigen::VectorXd::Zero(2), xb = xa;
    a.apply(xa);
    b.apply(xb);
    const double off = xb(0) - xa(0);
    if (off > 0.15) {
      ++up;
      ASSERT_NEAR(off, 0.3, 1e-12);
    } else if (off < -0.15) {
      ++down;
      ASSERT_NEAR(off, -0.3, 1e-12);
    } else {
      ASSERT_EQ(off, 0.0) << "the white noise changed with glitches added, sample " << k;
    }
    ASSERT_EQ(xb(1), 0.0);
  }
  const double n = draws, p = 0.002, sd = std::sqrt(n * p * (1.0 - p));
  EXPECT_NEAR(static_cast<double>(up + down), n * p, 4.0 * sd);
  EXPECT_NEAR(static_cast<double>(up), 0.5 * static_cast<double>(up + down), 4.0 * std::sqrt(0.25 * (up + down)));
  EXPECT_EQ(b.glitches(), up + down);
  EXPECT_EQ(a.glitches(), 0);
  EXPECT_TRUE(glitchy.any());
  NoiseSpec bad = glitchy;
  bad.outlier_probability[0] = 1.5;
  EXPECT_THROW(SensorNoise(bad, kinds), std::invalid_argument);
  bad = glitchy;
  bad.outlier[0] = -0.1;
  EXPECT_THROW(SensorNoise(bad, kinds), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
