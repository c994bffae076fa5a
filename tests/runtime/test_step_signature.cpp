// Step signatures and their GLR (runtime/step_signature.hpp). The oracle is a filter
// written out here (a point mass in the plane, with a constant force on it as the
// filter's disturbance states, its gain from a Riccati iteration of its own): a step
// put into the true force is fitted back from the filter's innovations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

#include "tmpc/runtime/step_signature.hpp"

namespace tmpc {
namespace {

constexpr double kT = 0.05;

// xi = (p_x, p_y, v_x, v_y, f_x, f_y): unit mass, the force held constant by the model.
struct PointMass {
  Eigen::MatrixXd A, C, L;
  Eigen::VectorXd sd;  // steady innovation deviations
  double noise = 0.01;
};

PointMass point_mass() {
  PointMass s;
  s.A = Eigen::MatrixXd::Identity(6, 6);
  for (int i = 0; i < 2; ++i) {
    s.A(i, 2 + i) = kT;
    s.A(i, 4 + i) = 0.5 * kT * kT;
    s.A(2 + i, 4 + i) = kT;
  }
  s.C = Eigen::MatrixXd::Zero(4, 6);
  s.C.leftCols(4).setIdentity();  // positions and velocities measured
  const Eigen::MatrixXd Q = Eigen::VectorXd::Constant(6, 1e-6).asDiagonal();
  const Eigen::MatrixXd R = Eigen::VectorXd::Constant(4, s.noise * s.noise).asDiagonal();
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(6, 6);
  for (int k = 0; k < 5000; ++k) {  // a-priori covariance of the predict/update filter
    const Eigen::MatrixXd S = s.C * P * s.C.transpose() + R;
    const Eigen::MatrixXd K = P * s.C.transpose() * S.inverse();
    P = s.A * (P - K * s.C * P) * s.A.transpose() + Q;
  }
  const Eigen::MatrixXd S = s.C * P * s.C.transpose() + R;
  s.L = P * s.C.transpose() * S.inverse();
  s.sd = S.diagonal().cwiseSqrt();
  return s;
}

// Flies the filter on the true system (no input), a force step mu from period `onset`,
// white measurement noise of `noise_scale` times the design's; the window holds the
// whitened innovations of the last W periods when `periods` have run.
InnovationWindow fly(const PointMass& s, const Eigen::Vector2d& mu, int onset, int periods, double noise_scale,
                     std::mt19937_64& rng, int window) {
  std::normal_distribution<double> normal;
  InnovationWindow w(4, window);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(6), xi = Eigen::VectorXd::Zero(6), y(4), nu(4);
  for (int k = 0; k < periods; ++k) {
    if (k == onset) x.tail(2) += mu;
    y = s.C * x;
    for (int i = 0; i < 4; ++i) y(i) += noise_scale * s.noise * normal(rng);
    nu = y - s.C * xi;  // xi: the prediction
    w.push(nu.cwiseQuotient(s.sd));
    xi += s.L * nu;
    xi = s.A * xi;
    x = s.A * x;
  }
  return w;
}

TEST(StepSignature, ANoiseFreeStepIsFittedExactlyWithItsOnset) {
  const PointMass s = point_mass();
  const StepSignature both(s.A, s.C, s.L, s.sd, {4, 5}, 12);
  std::mt19937_64 rng(1);
  const Eigen::Vector2d mu(0.7, -0.3);
  // The force jumps at period 20; its first innovation is at 21; 26 periods: 5 of them.
  const InnovationWindow w = fly(s, mu, 20, 26, 0.0, rng, 12);
  Eigen::VectorXd step(2);
  const StepSignature::Fit f = both.fit(w, &step);
  EXPECT_EQ(f.onset, 5);
  EXPECT_NEAR(step(0), mu(0), 1e-9);
  EXPECT_NEAR(step(1), mu(1), 1e-9);
  double energy = 0.0;  // every innovation explained: l = |z|^2
  for (int age = 0; age < w.size(); ++age) energy += w.at(age).squaredNorm();
  EXPECT_NEAR(f.statistic, energy, 1e-9 * energy);
  // A step along x alone: the x column explains it all, the y column nothing.
  const StepSignature x_only(s.A, s.C, s.L, s.sd, {4}, 12), y_only(s.A, s.C, s.L, s.sd, {5}, 12);
  const InnovationWindow wx = fly(s, Eigen::Vector2d(0.5, 0.0), 20, 26, 0.0, rng, 12);
  EXPECT_NEAR(both.fit(wx).statistic - x_only.fit(wx).statistic, 0.0, 1e-9 * both.fit(wx).statistic);
  EXPECT_GT(both.fit(wx).statistic, 100.0);
  EXPECT_NEAR(y_only.fit(wx).statistic, 0.0, 1e-9);
}

// The nested test: with noise, a step along x read with the x column alone is rejected
// (every force explaining it significantly better) about as rarely as the chi-square
// quantile says; a step along y is rejected every time.
TEST(StepSignature, TheNestedTestRejectsAWrongColumnAndRarelyARightOne) {
  const PointMass s = point_mass();
  const StepSignature both(s.A, s.C, s.L, s.sd, {4, 5}, 12), x_only(s.A, s.C, s.L, s.sd, {4}, 12);
  const double threshold = chi_square_quantile(1, 0.99);
  std::mt19937_64 rng(3);
  int rejected_right = 0, rejected_wrong = 0;
  const int trials = 400;
  for (int t = 0; t < trials; ++t) {
    const InnovationWindow right = fly(s, Eigen::Vector2d(0.6, 0.0), 100, 106, 1.0, rng, 12);
    const InnovationWindow wrong = fly(s, Eigen::Vector2d(0.0, 0.6), 100, 106, 1.0, rng, 12);
    rejected_right += both.fit(right).statistic - x_only.fit(right).statistic > threshold;
    rejected_wrong += both.fit(wrong).statistic - x_only.fit(wrong).statistic > threshold;
  }
  std::printf("rejected: %d of %d right steps, %d of %d wrong ones\n", rejected_right, trials, rejected_wrong, trials);
  EXPECT_LE(rejected_right, trials / 20);  // 1 % nominal; the onset's maximization and the window add some
  EXPECT_EQ(rejected_wrong, trials);
}

// A step along any direction of the disturbance states (StepSignature::along: an
// actuator's step is one, its input column mapped onto them): without noise the fit
// gives the step along the direction exactly, and jump(onset) times it is the filter's
// prediction error at the newest period (the oracle: the true state minus the
// prediction of the filter flown above); read_step() gives the fit's step without a
// prior and with a wide one (the window determines it), nothing with a narrow one, and
// of two directions reads the one the window determines, leaving the other at zero.
TEST(StepSignature, AStepAlongADirectionIsFittedAndItsJumpIsThePredictionError) {
  const PointMass s = point_mass();
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(6, 1);
  E(4, 0) = 0.6;
  E(5, 0) = 0.8;
  const StepSignature along = StepSignature::along(s.A, s.C, s.L, s.sd, E, 12);
  EXPECT_EQ(along.directions(), 1);
  EXPECT_TRUE(along.columns().empty());
  const double mu = 0.9;
  InnovationWindow w(4, 12);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(6), xi = Eigen::VectorXd::Zero(6), nu(4);
  const int onset = 20, periods = 27;  // the first innovation at 21, the newest at 26: onset 6
  for (int k = 0; k < periods; ++k) {
    if (k == onset) x += E * mu;
    nu = s.C * x - s.C * xi;
    w.push(nu.cwiseQuotient(s.sd));
    if (k == periods - 1) break;  // xi stays the newest prediction
    xi += s.L * nu;
    xi = s.A * xi;
    x = s.A * x;
  }
  Eigen::VectorXd step(1);
  const StepSignature::Fit f = along.fit(w, &step);
  EXPECT_EQ(f.onset, 6);
  EXPECT_NEAR(step(0), mu, 1e-9);
  const Eigen::VectorXd error = x - xi;
  EXPECT_GT(error.norm(), 0.01);
  EXPECT_LT((along.jump(f.onset) * step - error).norm(), 1e-9 * error.norm());
  Eigen::VectorXd map(1);
  along.read_step(w, f.onset, map);
  EXPECT_NEAR(map(0), mu, 1e-9) << "no prior: the fit's step";
  const StepSignature wide = StepSignature::along(s.A, s.C, s.L, s.sd, E, 12, Eigen::VectorXd::Constant(1, 100.0));
  const StepSignature narrow = StepSignature::along(s.A, s.C, s.L, s.sd, E, 12, Eigen::VectorXd::Constant(1, 1e-4));
  wide.read_step(w, f.onset, map);
  EXPECT_NEAR(map(0), mu, 1e-9);
  narrow.read_step(w, f.onset, map);
  EXPECT_EQ(map(0), 0.0);
  const StepSignature two = StepSignature::along(s.A, s.C, s.L, s.sd, Eigen::MatrixXd::Identity(6, 6).rightCols(2), 12,
                                                 Eigen::Vector2d(100.0, 1e-4));
  Eigen::VectorXd pair(2);
  two.read_step(w, f.onset, pair);
  EXPECT_NEAR(pair(0), 0.6 * mu, 1e-9);
  EXPECT_EQ(pair(1), 0.0);
  // A direction in the measured states, a prior of the wrong size or sign: refused.
  Eigen::MatrixXd measured = E;
  measured(2, 0) = 1.0;
  EXPECT_THROW(StepSignature::along(s.A, s.C, s.L, s.sd, measured, 12), std::invalid_argument);
  EXPECT_THROW(StepSignature::along(s.A, s.C, s.L, s.sd, E, 12, Eigen::VectorXd::Ones(2)), std::invalid_argument);
  EXPECT_THROW(StepSignature::along(s.A, s.C, s.L, s.sd, E, 12, -Eigen::VectorXd::Ones(1)), std::invalid_argument);
  EXPECT_THROW(StepSignature::along(s.A, s.C, s.L, s.sd, Eigen::MatrixXd::Zero(5, 1), 12), std::invalid_argument);
  EXPECT_THROW(StepSignature::along(s.A, s.C, s.L, s.sd, E, 12, Eigen::VectorXd::Ones(1), 1.0), std::invalid_argument);
}

TEST(StepSignature, TheWindowKeepsTheNewestInOrder) {
  InnovationWindow w(2, 3);
  EXPECT_EQ(w.size(), 0);
  for (int k = 1; k <= 5; ++k) w.push(Eigen::Vector2d(k, -k));
  EXPECT_EQ(w.size(), 3);
  EXPECT_EQ(w.at(0)(0), 5.0);
  EXPECT_EQ(w.at(1)(1), -4.0);
  EXPECT_EQ(w.at(2)(0), 3.0);
  w.clear();
  EXPECT_EQ(w.size(), 0);
  EXPECT_THROW(InnovationWindow(0, 3), std::invalid_argument);
  EXPECT_THROW(InnovationWindow(2, 0), std::invalid_argument);
}

TEST(StepSignature, BadInputIsRefusedNamingWhat) {
  const PointMass s = point_mass();
  auto message = [&](const Eigen::MatrixXd& C, const Eigen::VectorXd& sd, std::vector<Eigen::Index> cols, int window) {
    try {
      StepSignature(s.A, C, s.L, sd, cols, window);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(s.C.topRows(3), s.sd, {4}, 5).find("do not fit"), std::string::npos);
  EXPECT_NE(message(s.C, -s.sd, {4}, 5).find("deviation"), std::string::npos);
  EXPECT_NE(message(s.C, s.sd, {6}, 5).find("column 6 outside"), std::string::npos);
  EXPECT_NE(message(s.C, s.sd, {2}, 5).find("column 2 is measured"), std::string::npos);
  EXPECT_NE(message(s.C, s.sd, {}, 5).find("no column"), std::string::npos);
  EXPECT_NE(message(s.C, s.sd, {4}, 0).find("window 0"), std::string::npos);
}

// Against the table (Abramowitz and Stegun 26.8): the approximation within 3 % for
// two or more degrees of freedom.
TEST(StepSignature, ChiSquareQuantilesMatchTheTable) {
  struct Row {
    int dof;
    double p, table;
  };
  for (const Row& r : {Row{2, 0.999, 13.816}, Row{5, 0.999, 20.515}, Row{10, 0.999, 29.588}, Row{2, 0.95, 5.991},
                       Row{10, 0.95, 18.307}, Row{1, 0.95, 3.841}}) {
    EXPECT_NEAR(chi_square_quantile(r.dof, r.p), r.table, 0.03 * r.table) << r.dof << " " << r.p;
  }
  EXPECT_THROW(chi_square_quantile(0, 0.9), std::invalid_argument);
  EXPECT_THROW(chi_square_quantile(2, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
