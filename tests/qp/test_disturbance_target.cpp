// Offset-free form: the steady-state target against the model it must satisfy, and
// the offset-free QP against a plain simulation of the affine nominal model
// x+ = A x + B u + D d + c around that target.
#include <gtest/gtest.h>

#include <random>

#include "tmpc/qp/disturbance_target.hpp"
#include "tmpc/qp/parametric_qp.hpp"

namespace tmpc {
namespace {

struct Plant {
  Eigen::MatrixXd A, B, D;
};

// A double integrator pair with an integral state: x = (p, v, q, w, int p), inputs
// (force on v, force on w), two disturbance forces. Zero p and int p at steady state.
Plant integrator_plant() {
  const double T = 0.1;
  Plant p;
  p.A = Eigen::MatrixXd::Identity(5, 5);
  p.A(0, 1) = T;
  p.A(1, 0) = -0.2 * T;  // a spring on p
  p.A(2, 3) = T;
  p.A(3, 2) = -0.5 * T;
  p.A(3, 3) = 1.0 - 0.1 * T;
  p.A(4, 0) = T;
  p.B = Eigen::MatrixXd::Zero(5, 2);
  p.B(1, 0) = T;
  p.B(3, 1) = T;
  p.B(1, 1) = 0.3 * T;  // coupled actuators
  p.D = Eigen::MatrixXd::Zero(5, 2);
  p.D(1, 0) = T;
  p.D(3, 1) = T;
  p.D(1, 1) = -0.2 * T;
  return p;
}

TEST(DisturbanceTarget, IsASteadyStateWithTheListedStatesAtZero) {
  const Plant p = integrator_plant();
  const std::vector<int> zero = {0, 4};
  const DisturbanceTarget t = steady_state_target(p.A, p.B, p.D, zero);
  ASSERT_EQ(t.Tx.rows(), 5);
  ASSERT_EQ(t.Tx.cols(), 2);
  ASSERT_EQ(t.Tu.rows(), 2);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  for (int k = 0; k < 20; ++k) {
    const Eigen::Vector2d d(g(rng), g(rng));
    const Eigen::VectorXd xs = t.Tx * d, us = t.Tu * d;
    // x_s = A x_s + B u_s + D d, simulated one step.
    EXPECT_LT((p.A * xs + p.B * us + p.D * d - xs).norm(), 1e-12 * (1.0 + d.norm()));
    for (int i : zero) EXPECT_LT(std::abs(xs(i)), 1e-12);
    EXPECT_GT(us.norm(), 1e-3 * d.norm());  // the inputs take up the force
  }
}

TEST(DisturbanceTarget, NamesTheChannelWithoutASteadyState) {
  Plant p = integrator_plant();
  p.B.setZero();  // nothing can balance the force with p held at zero
  try {
    steady_state_target(p.A, p.B, p.D, {0, 1, 2, 3, 4});
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("disturbance channel 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(steady_state_target(p.A, p.B, Eigen::MatrixXd::Ones(4, 1), {0}), std::invalid_argument);
  EXPECT_THROW(steady_state_target(p.A, p.B, p.D, {7}), std::invalid_argument);
}

TEST(DisturbancePseudoInverse, RecoversTheForceFromTheObservedRows) {
  const Plant p = integrator_plant();
  const Eigen::MatrixXd Dp = disturbance_pseudo_inverse(p.D, {1, 3});
  ASSERT_EQ(Dp.rows(), 2);
  ASSERT_EQ(Dp.cols(), 5);
  const Eigen::Vector2d d(0.7, -1.3);
  Eigen::VectorXd r = p.D * d;
  r(0) += 5.0;  // rows outside the observed set do not matter
  EXPECT_LT((Dp * r - d).norm(), 1e-12);
  EXPECT_THROW(disturbance_pseudo_inverse(p.D, {1}), std::invalid_argument);  // rank 1 < 2
  EXPECT_THROW(disturbance_pseudo_inverse(p.D, {9}), std::invalid_argument);
}

TEST(OffsetFreeQp, IsTheAffineModelAroundTheTarget) {
  const Plant p = integrator_plant();
  const int n = 5, m = 2, nd = 2;
  for (const auto& [N, M] : {std::pair<int, int>{6, 6}, {8, 3}, {1, 1}}) {
    Eigen::MatrixXd W = Eigen::MatrixXd::Identity(n, n);
    W(1, 1) = 0.5;
    const Eigen::MatrixXd Wu = 0.3 * Eigen::MatrixXd::Identity(m, m);
    MpcQpData d = build_mpc_qp(p.A, p.B, W, Wu, 2.0 * W, Box::symmetric(Eigen::VectorXd::Ones(n)),
                               Box::symmetric(Eigen::VectorXd::Ones(m)), N, M);
    const DisturbanceTarget t = steady_state_target(p.A, p.B, p.D, {0, 4});
    make_offset_free(d, t.Tx, t.Tu);
    ASSERT_EQ(d.parameters(), n + nd + n);
    const ParametricQp qp = ParametricQp::from_mpc(d);
    ASSERT_EQ(qp.nx(), n + nd + n);
    std::mt19937_64 rng(11 + N);
    std::normal_distribution<double> g;
    auto randn = [&](int k) {
      Eigen::VectorXd v(k);
      for (int i = 0; i < k; ++i) v(i) = g(rng);
      return v;
    };
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::VectorXd dx0 = randn(n), dist = randn(nd), c = 0.1 * randn(n);
      Eigen::VectorXd theta(qp.nx());
      theta << dx0, dist, c;
      const Eigen::VectorXd xs = t.Tx * dist, us = t.Tu * dist;
      // Absolute inputs and states of the affine model from x_bar = x_s + dx0.
      auto simulate = [&](const Eigen::VectorXd& z, Eigen::VectorXd& rows, double& cost) {
        rows.resize(qp.nc());
        Eigen::VectorXd x = xs + dx0;
        cost = 0.0;
        for (int i = 0; i < M; ++i) rows.segment(i * m, m) = z.segment(i * m, m) + us;
        for (int i = 0; i < N; ++i) {
          const Eigen::VectorXd u = z.segment(std::min(i, M - 1) * m, m) + us;
          cost += (u - us).dot(Wu * (u - us));
          x = p.A * x + p.B * u + p.D * dist + c;
          rows.segment(M * m + i * n, n) = x;
          cost += (x - xs).dot((i == N - 1 ? 2.0 * W : W) * (x - xs));
        }
      };
      const Eigen::VectorXd z1 = randn(M * m), z2 = randn(M * m);
      Eigen::VectorXd rows1, rows2;
      double c1 = 0, c2 = 0;
      simulate(z1, rows1, c1);
      simulate(z2, rows2, c2);
      // lo0 <= A z + E theta <= hi0 holds the absolute inputs and states.
      EXPECT_LT((qp.A * z1 + qp.E * theta - rows1).cwiseAbs().maxCoeff(), 1e-10) << "N " << N << " M " << M;
      // The QP's objective differs from the simulated cost by a constant in theta.
      Eigen::VectorXd f, lo, hi;
      qp.instance_into(theta, f, lo, hi);
      const double q1 = 0.5 * z1.dot(qp.H * z1) + f.dot(z1), q2 = 0.5 * z2.dot(qp.H * z2) + f.dot(z2);
      EXPECT_NEAR(q1 - q2, c1 - c2, 1e-9 * (1.0 + std::abs(c1 - c2))) << "N " << N << " M " << M;
    }
  }
}

}  // namespace
}  // namespace tmpc
