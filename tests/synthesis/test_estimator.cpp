// The Kalman filter of the offset-free error model and the output-feedback tube
// (estimator.hpp), on a double integrator with a force disturbance: the gain against
// the filter Riccati equation written here, the filter's error statistics against its
// covariance by simulation, the disturbance estimate against the true force, and the
// tube's sets by simulating the closed loop under bounded noise (sampled invariance),
// its Gaussian form's standard deviations by simulating it under white Gaussian noise;
// the filter's start against the batch estimate of the trajectory.
#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include "tmpc/sets/box.hpp"
#include "tmpc/synthesis/estimator.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {
namespace {

constexpr double T = 0.05;

struct Plant {
  Eigen::MatrixXd A, B, D;
};

Plant double_integrator() {
  Plant p;
  p.A = (Eigen::Matrix2d() << 1, T, 0, 1).finished();
  p.B = (Eigen::Vector2d() << 0.5 * T * T, T).finished();
  p.D = (Eigen::Vector2d() << 0.5 * T * T, T).finished();  // a force on the mass
  return p;
}

TEST(Kalman, TheGainSolvesTheFilterRiccatiEquation) {
  const Plant p = double_integrator();
  const Eigen::Matrix3d Q = Eigen::Vector3d(1e-6, 1e-6, 1e-4).asDiagonal();
  const Eigen::Matrix<double, 1, 1> R = Eigen::Matrix<double, 1, 1>::Constant(1e-4);
  const KalmanDesign k = design_kalman(p.A, p.B, p.D, Eigen::MatrixXd(2, 0), {0}, Q, R);
  ASSERT_EQ(k.L.rows(), 3);
  ASSERT_EQ(k.L.cols(), 1);
  // P = A P A' - A P C' (C P C' + R)^-1 C P A' + Q, written from the definition.
  const Eigen::MatrixXd& A = k.A_a;
  const Eigen::MatrixXd& C = k.C;
  const Eigen::MatrixXd S = C * k.P * C.transpose() + R;
  const Eigen::MatrixXd rhs = A * k.P * A.transpose() - A * k.P * C.transpose() * S.inverse() * C * k.P * A.transpose() + Q;
  EXPECT_LT((rhs - k.P).norm() / k.P.norm(), 1e-9);
  EXPECT_LT((k.L - k.P * C.transpose() * S.inverse()).norm(), 1e-9 * k.L.norm());
  EXPECT_LT(k.spectral_radius, 1.0);
  // Undetectable: a disturbance on the velocity measured nowhere and a second copy of it.
  const Eigen::MatrixXd D2 = (Eigen::MatrixXd(2, 2) << 0.5 * T * T, 0.5 * T * T, T, T).finished();
  EXPECT_THROW(design_kalman(p.A, p.B, D2, Eigen::MatrixXd(2, 0), {0}, Eigen::Vector4d(1e-6, 1e-6, 1e-4, 1e-4).asDiagonal(), R),
               std::runtime_error);
}

TEST(Kalman, TheFilterFindsTheForceAndItsErrorHasTheDesignedCovariance) {
  const Plant p = double_integrator();
  const Eigen::Vector3d q(1e-6, 1e-6, 1e-4);
  const double r = 1e-4;
  const KalmanDesign k = design_kalman(p.A, p.B, p.D, Eigen::MatrixXd(2, 0), {0}, q.asDiagonal(),
                                       Eigen::Matrix<double, 1, 1>::Constant(r));
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  Eigen::Vector3d xi(0.3, 0.0, 0.0), est = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  const int burn = 2000, steps = 40000;
  for (int t = 0; t < burn + steps; ++t) {
    const double u = -2.0 * est(0) - 1.5 * est(1) - est(2);  // any input: the filter sees it
    Eigen::Vector3d w;
    for (int i = 0; i < 3; ++i) w(i) = std::sqrt(q(i)) * normal(rng);
    xi = k.A_a * xi + k.B_a * u + w;
    const double y = xi(0) + std::sqrt(r) * normal(rng);
    const Eigen::Vector3d pred = k.A_a * est + k.B_a * u;
    est = pred + k.L * (y - pred(0));
    if (t >= burn) {
      const Eigen::Vector3d e = xi - est;
      mean += e;
      cov += e * e.transpose();
    }
  }
  mean /= steps;
  cov /= steps;
  // A-posteriori covariance (I - L C) P.
  const Eigen::Matrix3d expected = (Eigen::Matrix3d::Identity() - k.L * k.C) * k.P;
  std::printf("error variance: simulated (%.3g, %.3g, %.3g), designed (%.3g, %.3g, %.3g); mean force error %.2e\n",
              cov(0, 0), cov(1, 1), cov(2, 2), expected(0, 0), expected(1, 1), expected(2, 2), mean(2));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(cov(i, i), expected(i, i), 0.15 * expected(i, i)) << i;
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(mean(i)), 5.0 * std::sqrt(expected(i, i) / steps) * 30.0) << i;
}

TEST(OutputFeedbackTube, TheSetsHoldTheSimulatedLoopUnderBoundedNoise) {
  const Plant p = double_integrator();
  const KalmanDesign k = design_kalman(p.A, p.B, p.D, Eigen::MatrixXd(2, 0), {0}, Eigen::Vector3d(1e-6, 1e-6, 1e-4).asDiagonal(),
                                       Eigen::Matrix<double, 1, 1>::Constant(1e-4));
  const LqrResult lqr = solve_dlqr(p.A, p.B, Eigen::Vector2d(10.0, 1.0).asDiagonal(), Eigen::Matrix<double, 1, 1>::Constant(0.1));
  const Eigen::MatrixXd K = lqr.K;
  const Eigen::Vector3d W_a(1e-4, 1e-4, 2e-3);  // state mismatch, the force's change per step
  const Eigen::VectorXd V = Eigen::VectorXd::Constant(1, 0.02);
  const Box X = Box::symmetric(Eigen::Vector2d(1.0, 2.0)), U = Box::symmetric(Eigen::VectorXd::Constant(1, 5.0));
  const OutputFeedbackTube t = output_feedback_tube(k, {p.A + p.B * K}, K, W_a, V, X, U, 0.05);
  ASSERT_FALSE(t.x_bar.empty());
  ASSERT_GT(t.noise_margin, 1.0);
  const Zonotope E = t.E_W.plus(t.E_V);
  // The loop: x_bar stays 0 (u_bar = 0), u = K x_hat; w and v at random corners of
  // their boxes (the worst case the sets must hold), the force a bounded random walk.
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> coin(0, 1);
  auto corner = [&](double h) { return coin(rng) ? h : -h; };
  std::normal_distribution<double> normal;
  std::vector<Eigen::Vector3d> dirs_e;
  std::vector<Eigen::Vector2d> dirs_z;
  std::vector<double> h_e, h_z;  // the sets' support functions in those directions
  for (int i = 0; i < 200; ++i) {
    dirs_e.push_back(Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized());
    dirs_z.push_back(Eigen::Vector2d(normal(rng), normal(rng)).normalized());
    h_e.push_back(E.support(dirs_e.back()));
    h_z.push_back(t.Z_c.support(dirs_z.back()));
  }
  double worst_e = 0.0, worst_z = 0.0;
  for (int run = 0; run < 20; ++run) {
    Eigen::Vector3d xi = Eigen::Vector3d::Zero(), est = Eigen::Vector3d::Zero();
    for (int step = 0; step < 3000; ++step) {
      const double u = (K * est.head(2))(0);
      const Eigen::Vector3d w(corner(W_a(0)), corner(W_a(1)), corner(W_a(2)));
      xi = k.A_a * xi + k.B_a * u + w;
      const double y = xi(0) + corner(V(0));
      const Eigen::Vector3d pred = k.A_a * est + k.B_a * u;
      est = pred + k.L * (y - pred(0));
      const Eigen::Vector3d e = xi - est;
      const Eigen::Vector2d delta = est.head(2);
      for (std::size_t i = 0; i < dirs_e.size(); ++i) {
        worst_e = std::max(worst_e, dirs_e[i].dot(e) / h_e[i]);
        worst_z = std::max(worst_z, dirs_z[i].dot(delta) / h_z[i]);
      }
    }
  }
  std::printf("sampled: estimation error at %.3f of E's support, control error at %.3f of Z_c's (<= 1: inside); "
              "noise margin %.3f\n", worst_e, worst_z, t.noise_margin);
  EXPECT_LE(worst_e, 1.0);
  EXPECT_LE(worst_z, 1.0);
  EXPECT_GT(worst_e, 0.1);  // the samples reach into the sets: the test can fail
  // The noise margin is where the sets empty: recomputed just below and above it.
  const OutputFeedbackTube below = output_feedback_tube(k, {p.A + p.B * K}, K, W_a, V * (0.99 * t.noise_margin), X, U, 0.05);
  const OutputFeedbackTube above = output_feedback_tube(k, {p.A + p.B * K}, K, W_a, V * (1.01 * t.noise_margin), X, U, 0.05);
  EXPECT_FALSE(below.x_bar.empty() || below.u_bar.empty());
  EXPECT_TRUE(above.x_bar.empty() || above.u_bar.empty());
}

TEST(OutputFeedbackTube, TheGaussianFormHasTheSimulatedLoopsStandardDeviations) {
  // The loop of the test above with w = 0, v white Gaussian of std sigma (the noise
  // part alone) and the force estimate compensated: x - x_bar and u - u_bar sampled over long runs against x_sigmas_v and
  // u_sigmas_v for V = sigma (one standard deviation), and the share of steps outside
  // 3 sigma against a normal's.
  const Plant p = double_integrator();
  const KalmanDesign k = design_kalman(p.A, p.B, p.D, Eigen::MatrixXd(2, 0), {0}, Eigen::Vector3d(1e-6, 1e-6, 1e-4).asDiagonal(),
                                       Eigen::Matrix<double, 1, 1>::Constant(1e-4));
  const Eigen::MatrixXd K = solve_dlqr(p.A, p.B, Eigen::Vector2d(10.0, 1.0).asDiagonal(), Eigen::Matrix<double, 1, 1>::Constant(0.1)).K;
  const double sigma = 0.01;
  const Box X = Box::symmetric(Eigen::Vector2d(1.0, 2.0)), U = Box::symmetric(Eigen::VectorXd::Constant(1, 5.0));
  const OutputFeedbackTube t = output_feedback_tube(k, {p.A + p.B * K}, K, Eigen::Vector3d(1e-4, 1e-4, 2e-3),
                                                    Eigen::VectorXd::Constant(1, sigma), X, U, 0.05);
  ASSERT_EQ(t.x_sigmas_v.size(), 2);
  ASSERT_EQ(t.u_sigmas_v.size(), 1);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  Eigen::Vector2d sum_sq = Eigen::Vector2d::Zero();
  double u_sq = 0.0;
  long outside = 0, samples = 0;
  for (int run = 0; run < 8; ++run) {
    Eigen::Vector3d xi = Eigen::Vector3d::Zero(), est = Eigen::Vector3d::Zero();
    for (int step = 0; step < 20000; ++step) {
      // x_bar = 0; the offset-free law's input target cancels the force estimate
      // (matched here: D = B), u_bar = -d_hat, so x_hat+ = (A + B K) x_hat + L_x nu.
      const double u = (K * est.head(2))(0) - est(2);
      xi = k.A_a * xi + k.B_a * u;
      const double y = xi(0) + sigma * normal(rng);
      const Eigen::Vector3d pred = k.A_a * est + k.B_a * u;
      est = pred + k.L * (y - pred(0));
      if (step < 2000) continue;  // the filter's and loop's transients
      sum_sq += xi.head(2).cwiseAbs2();
      const double u_next = (K * est.head(2))(0);
      u_sq += u_next * u_next;
      for (int i = 0; i < 2; ++i) outside += std::abs(xi(i)) > 3.0 * t.x_sigmas_v(i);
      ++samples;
    }
  }
  const Eigen::Vector2d sd = (sum_sq / static_cast<double>(samples)).cwiseSqrt();
  const double sd_u = std::sqrt(u_sq / static_cast<double>(samples));
  std::printf("x - x_bar std: simulated (%.4g, %.4g), computed (%.4g, %.4g); u: %.4g, %.4g; outside 3 sigma %.3f %%\n",
              sd(0), sd(1), t.x_sigmas_v(0), t.x_sigmas_v(1), sd_u, t.u_sigmas_v(0),
              100.0 * static_cast<double>(outside) / static_cast<double>(2 * samples));
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(sd(i), t.x_sigmas_v(i), 0.05 * t.x_sigmas_v(i)) << i;
  EXPECT_NEAR(sd_u, t.u_sigmas_v(0), 0.05 * t.u_sigmas_v(0));
  // A normal leaves +-3 sigma 0.27 % of the time.
  EXPECT_LT(static_cast<double>(outside) / static_cast<double>(2 * samples), 0.006);
  EXPECT_GT(t.noise_margin_gaussian, t.noise_margin);  // white noise averages; a bias in the box does not
  // Its noise margin is where its sets empty.
  const OutputFeedbackTube below = output_feedback_tube(k, {p.A + p.B * K}, K, Eigen::Vector3d(1e-4, 1e-4, 2e-3),
                                                        Eigen::VectorXd::Constant(1, 0.99 * sigma * t.noise_margin_gaussian), X, U, 0.05);
  const OutputFeedbackTube above = output_feedback_tube(k, {p.A + p.B * K}, K, Eigen::Vector3d(1e-4, 1e-4, 2e-3),
                                                        Eigen::VectorXd::Constant(1, 1.01 * sigma * t.noise_margin_gaussian), X, U, 0.05);
  EXPECT_FALSE(below.x_bar_gaussian.empty() || below.u_bar_gaussian.empty());
  EXPECT_TRUE(above.x_bar_gaussian.empty() || above.u_bar_gaussian.empty());
}

TEST(StationaryCovariance, SolvesTheLyapunovEquationAndRefusesAnUnstableLoop) {
  const Eigen::Matrix2d A = (Eigen::Matrix2d() << 0.9, 0.2, -0.1, 0.95).finished();
  const Eigen::Matrix2d Q = (Eigen::Matrix2d() << 2.0, 0.3, 0.3, 1.0).finished();
  const Eigen::MatrixXd S = stationary_covariance(A, Q);
  EXPECT_LT((A * S * A.transpose() + Q - S).norm(), 1e-10 * S.norm());
  EXPECT_THROW(stationary_covariance(Eigen::Matrix2d::Identity() * 1.01, Q), std::runtime_error);
}

// The filter's start (estimator.hpp start_covariance(), start_gains()).
KalmanDesign start_test_filter() {
  const Plant p = double_integrator();
  return design_kalman(p.A, p.B, p.D, Eigen::MatrixXd(2, 0), {0}, Eigen::Vector3d(1e-6, 1e-6, 1e-4).asDiagonal(),
                       Eigen::Matrix<double, 1, 1>::Constant(1e-4));
}

TEST(KalmanStart, ThePriorHasTheForceUnknownAndTheStateWithinItsNoise) {
  const KalmanDesign k = start_test_filter();
  const Eigen::MatrixXd P0 = start_covariance(k, 1, 2.0, 0.0, 0.5);
  // Measured position: (0.5 sigma)^2; unmeasured velocity: its steady variance; force 2^2.
  EXPECT_DOUBLE_EQ(P0(0, 0), 0.25 * 1e-4);
  EXPECT_DOUBLE_EQ(P0(1, 1), k.P(1, 1));
  EXPECT_DOUBLE_EQ(P0(2, 2), 4.0);
  EXPECT_EQ((P0 - Eigen::MatrixXd(P0.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 0.0);  // uncorrelated
  // Zeros keep the steady covariance, correlations included.
  EXPECT_EQ(start_covariance(k, 1, 0.0, 0.0, 0.0), k.P);
  EXPECT_THROW(start_covariance(k, 1, -1.0, 0.0, 0.5), std::invalid_argument);
  EXPECT_THROW(start_covariance(k, 3, 1.0, 0.0, 0.5), std::invalid_argument);
}

// open_states: the chosen states lose every correlation and take the given variance;
// the rest of P is untouched (entry by entry against a dense P with no zero entry).
TEST(KalmanStart, OpenStatesUnknownsTheChosenStatesAndKeepsTheRest) {
  Eigen::MatrixXd P(4, 4);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) P(i, j) = 1.0 / (1.0 + i + j) + (i == j ? 1.0 : 0.0);  // a Hilbert matrix + I
  }
  Eigen::MatrixXd opened = P;
  open_states(opened, {1, 3}, 0.5);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const bool chosen = i == 1 || i == 3 || j == 1 || j == 3;
      EXPECT_EQ(opened(i, j), !chosen ? P(i, j) : i == j ? 0.25 : 0.0) << i << ", " << j;
    }
  }
  EXPECT_THROW(open_states(opened, {4}, 0.5), std::invalid_argument);
  EXPECT_THROW(open_states(opened, {-1}, 0.5), std::invalid_argument);
  EXPECT_THROW(open_states(opened, {0}, 0.0), std::invalid_argument);
  EXPECT_THROW(open_states(opened, {0}, std::nan("")), std::invalid_argument);
  // start_covariance opens its blocks the same way.
  const KalmanDesign k = start_test_filter();
  Eigen::MatrixXd by_hand = start_covariance(k, 1, 0.0, 0.0, 0.5);
  open_states(by_hand, {2}, 2.0);
  EXPECT_EQ(by_hand, start_covariance(k, 1, 2.0, 0.0, 0.5));
}

// Oracle: the filtered estimate of a linear Gaussian model is the last block of the
// batch MAP estimate of the whole trajectory (normal equations written here), so the
// scheduled gains, run as a filter, must give it at every step.
TEST(KalmanStart, TheScheduledFilterIsTheBatchEstimateOfTheTrajectory) {
  const KalmanDesign k = start_test_filter();
  const Eigen::MatrixXd P0 = start_covariance(k, 1, 2.0, 0.0, 0.5);
  const std::vector<Eigen::MatrixXd> gains = start_gains(k, P0);
  ASSERT_GT(gains.size(), 5u);
  ASSERT_LT(gains.size(), 70u);  // the batch checks run past the schedule's end
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  const int steps = 80;
  std::vector<double> y, u;
  Eigen::Vector3d xi(0.004, -0.01, 0.8);  // a force of 0.8 from the start
  for (int j = 0; j < steps; ++j) {
    y.push_back(xi(0) + 0.01 * normal(rng));
    u.push_back(std::sin(0.3 * j));
    xi = k.A_a * xi + k.B_a * u.back();
  }
  const Eigen::Matrix3d Qi = k.Q.inverse(), P0i = P0.inverse();
  const double Ri = 1.0 / k.R(0, 0);
  Eigen::Vector3d est = Eigen::Vector3d::Zero();  // the prior's mean
  for (int K = 0; K < steps; ++K) {
    if (K > 0) est = k.A_a * est + k.B_a * u[static_cast<std::size_t>(K - 1)];
    const Eigen::MatrixXd& L = static_cast<std::size_t>(K) < gains.size() ? gains[static_cast<std::size_t>(K)] : k.L;
    est += L * (y[static_cast<std::size_t>(K)] - est(0));
    if (K % 7 != 0 && K != steps - 1) continue;
    const int nz = 3 * (K + 1);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nz, nz);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(nz);
    H.topLeftCorner(3, 3) += P0i;
    for (int j = 0; j <= K; ++j) {
      H(3 * j, 3 * j) += Ri;
      g(3 * j) += Ri * y[static_cast<std::size_t>(j)];
    }
    for (int j = 0; j < K; ++j) {  // xi_j+1 - A xi_j - B u_j, weighted by Q^-1
      Eigen::MatrixXd E = Eigen::MatrixXd::Zero(3, nz);
      E.block(0, 3 * j, 3, 3) = -k.A_a;
      E.block(0, 3 * (j + 1), 3, 3) = Eigen::Matrix3d::Identity();
      H += E.transpose() * Qi * E;
      g += E.transpose() * Qi * (k.B_a * u[static_cast<std::size_t>(j)]);
    }
    const Eigen::VectorXd z = H.ldlt().solve(g);
    // Exact while scheduled; after it the steady gain, within the schedule's tolerance.
    const double tol = static_cast<std::size_t>(K) < gains.size() ? 1e-7 : 1e-4;
    EXPECT_LT((est - z.tail(3)).norm(), tol * (1.0 + z.tail(3).norm())) << "step " << K << " of " << gains.size();
  }
  // The schedule ends within its tolerance of the steady gain; from the steady
  // covariance it is the steady gain at once.
  EXPECT_LE((gains.back() - k.L).cwiseAbs().maxCoeff(), 1e-3 * k.L.cwiseAbs().maxCoeff());
  const std::vector<Eigen::MatrixXd> steady = start_gains(k, k.P);
  ASSERT_EQ(steady.size(), 1u);
  EXPECT_LT((steady.front() - k.L).norm(), 1e-9 * k.L.norm());
}

// What the start is for: a force present from the engagement is read in a fraction of
// the time the steady gain takes (mean squared error over noisy seeds).
TEST(KalmanStart, AForcePresentAtTheStartIsReadFasterThanByTheSteadyGain) {
  const KalmanDesign k = start_test_filter();
  const std::vector<Eigen::MatrixXd> gains = start_gains(k, start_covariance(k, 1, 2.0, 0.0, 0.5));
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  const int seeds = 200, horizon = 40;
  std::vector<double> mse_start(horizon, 0.0), mse_steady(horizon, 0.0);
  for (int s = 0; s < seeds; ++s) {
    Eigen::Vector3d xi(0.0, 0.0, 1.5), a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
    for (int j = 0; j < horizon; ++j) {
      const double y = xi(0) + 0.01 * normal(rng);
      if (j > 0) {
        a = k.A_a * a;
        b = k.A_a * b;
      }
      a += (static_cast<std::size_t>(j) < gains.size() ? gains[static_cast<std::size_t>(j)] : k.L) * (y - a(0));
      b += k.L * (y - b(0));
      mse_start[static_cast<std::size_t>(j)] += std::pow(a(2) - xi(2), 2) / seeds;
      mse_steady[static_cast<std::size_t>(j)] += std::pow(b(2) - xi(2), 2) / seeds;
      xi = k.A_a * xi;
    }
  }
  std::printf("force rms error after 10, 20, 39 steps: scheduled %.3f %.3f %.3f, steady %.3f %.3f %.3f (of 1.5)\n",
              std::sqrt(mse_start[10]), std::sqrt(mse_start[20]), std::sqrt(mse_start[39]), std::sqrt(mse_steady[10]),
              std::sqrt(mse_steady[20]), std::sqrt(mse_steady[39]));
  for (int j : {10, 20, 39}) EXPECT_LT(mse_start[static_cast<std::size_t>(j)], 0.25 * mse_steady[static_cast<std::size_t>(j)]) << j;
}

}  // namespace
}  // namespace tmpc
