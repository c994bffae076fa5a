// Prediction matrices and cost against a plain simulation of the nominal model with
// move blocking and the stage costs of (3.50).
#include <gtest/gtest.h>

#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/qp/parametric_qp.hpp"

namespace tmpc {
namespace {

MpcQpData random_data(int n, int m, int N, int M, unsigned seed) {
  std::srand(seed);
  const Eigen::MatrixXd A = 0.5 * Eigen::MatrixXd::Random(n, n) + Eigen::MatrixXd::Identity(n, n) * 0.5;
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, m);
  Eigen::MatrixXd Q = Eigen::MatrixXd::Random(n, n);
  Q = Q * Q.transpose() + Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd L = Eigen::MatrixXd::Random(n, n);
  L = L * L.transpose() + Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd R = Eigen::VectorXd::Random(m).cwiseAbs().array() + 0.5;
  return build_mpc_qp(A, B, Q, Eigen::MatrixXd(R.col(0).asDiagonal()), L, Box::symmetric(Eigen::VectorXd::Ones(n)),
                      Box::symmetric(Eigen::VectorXd::Ones(m)), N, M);
}

TEST(MpcQp, PredictionAndCostMatchASimulation) {
  for (const auto& [N, M] : {std::pair<int, int>{6, 6}, {6, 2}, {5, 1}, {1, 1}}) {
    const int n = 3, m = 2;
    const MpcQpData d = random_data(n, m, N, M, 7u + static_cast<unsigned>(N * 10 + M));
    const Eigen::VectorXd x0 = Eigen::VectorXd::Random(n);
    const Eigen::VectorXd u = Eigen::VectorXd::Random(M * m);
    Eigen::VectorXd x = x0;
    double cost = 0.0;
    const Eigen::VectorXd xhat = d.P * u + d.Q * x0;
    for (int i = 0; i < N; ++i) {
      const Eigen::VectorXd ui = u.segment(std::min(i, M - 1) * m, m);
      cost += ui.dot(d.Sigma_lambda * ui);  // l(x(i), u(i)) for i = 0..N-1 (x(0) is a constant)
      x = d.A * x + d.B * ui;
      ASSERT_LT((xhat.segment(i * n, n) - x).norm(), 1e-12) << "N=" << N << " M=" << M << " step " << i;
      cost += (i == N - 1) ? x.dot(d.L * x) : x.dot(d.Sigma_rho * x);
    }
    EXPECT_NEAR(mpc_cost(d, x0, u), cost, 1e-10 * std::abs(cost));
    const CondensedQp qp = condensed_qp(d, x0);
    EXPECT_NEAR(0.5 * u.dot(qp.H * u) + qp.f.dot(u) + qp.constant, cost, 1e-9 * std::abs(cost));
    // Constraint rows: inputs then predicted states shifted by Q x0.
    const Eigen::VectorXd Az = qp.A * u;
    EXPECT_LT((Az.head(M * m) - u).norm(), 1e-15);
    EXPECT_LT((Az.tail(N * n) + d.Q * x0 - xhat).norm(), 1e-12);
  }
}

/// The input-rate term by its definition: sum_i (u(i) - u(i-1))' S (u(i) - u(i-1)),
/// u(-1) = v_prev, over the M free inputs.
double rate_cost(const Eigen::MatrixXd& S, const Eigen::VectorXd& u, const Eigen::VectorXd& v_prev, int M, int m) {
  double c = 0.0;
  Eigen::VectorXd before = v_prev;
  for (int i = 0; i < M; ++i) {
    const Eigen::VectorXd step = u.segment(i * m, m) - before;
    c += step.dot(S * step);
    before = u.segment(i * m, m);
  }
  return c;
}

TEST(MpcQp, InputRateWeightPenalizesEachMoveFromThePreviousInput) {
  for (const auto& [N, M] : {std::pair<int, int>{6, 6}, {6, 3}, {5, 1}, {1, 1}}) {
    const int n = 3, m = 2;
    const MpcQpData hard = random_data(n, m, N, M, 11u + static_cast<unsigned>(N * 10 + M));
    MpcQpData d = hard;
    const Eigen::MatrixXd S = Eigen::Vector2d(0.7, 3.0).asDiagonal();
    add_input_rate_weight(d, S);
    ASSERT_TRUE(d.rate_weighted());
    ASSERT_EQ(d.parameters(), n + m);
    const ParametricQp p = ParametricQp::from_mpc(d);
    ASSERT_EQ(p.nx(), n + m);
    EXPECT_LT(p.E.rightCols(m).cwiseAbs().maxCoeff(), 1e-300);  // v_prev moves no bound
    const Eigen::VectorXd x0 = Eigen::VectorXd::Random(n), v = Eigen::VectorXd::Random(m);
    Eigen::VectorXd theta(n + m);
    theta << x0, v;
    const Eigen::VectorXd f = p.f0 + p.F * theta;
    // The QP's objective and the cost by definition (the hard cost from mpc_cost, checked
    // against a simulation above) differ by a constant: the same for every u.
    double offset = 0.0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::VectorXd u = Eigen::VectorXd::Random(M * m);
      const double q = 0.5 * u.dot(p.H * u) + f.dot(u);
      const double cost = mpc_cost(hard, x0, u) + rate_cost(S, u, v, M, m);
      if (k == 0) offset = cost - q;
      EXPECT_NEAR(cost - q, offset, 1e-10 * (1.0 + std::abs(cost))) << "N=" << N << " M=" << M << " sample " << k;
      EXPECT_NEAR(mpc_cost(d, x0, u, v), cost, 1e-10 * (1.0 + std::abs(cost)));
    }
  }
}

TEST(MpcQp, InputRateWeightRefusesWhatIsNotAWeight) {
  MpcQpData d = random_data(3, 2, 4, 2, 3);
  EXPECT_THROW(add_input_rate_weight(d, Eigen::MatrixXd::Identity(3, 3)), std::invalid_argument);     // size
  EXPECT_THROW(add_input_rate_weight(d, -Eigen::MatrixXd::Identity(2, 2)), std::invalid_argument);    // indefinite
  Eigen::MatrixXd asym = Eigen::MatrixXd::Identity(2, 2);
  asym(0, 1) = 0.5;
  EXPECT_THROW(add_input_rate_weight(d, asym), std::invalid_argument);
  add_input_rate_weight(d, Eigen::MatrixXd::Zero(2, 2));  // zero: no weight, no parameter
  EXPECT_FALSE(d.rate_weighted());
  EXPECT_EQ(d.parameters(), 3);
  add_input_rate_weight(d, Eigen::MatrixXd::Identity(2, 2));
  EXPECT_THROW(add_input_rate_weight(d, Eigen::MatrixXd::Identity(2, 2)), std::invalid_argument);  // twice
  EXPECT_THROW(make_offset_free(d, Eigen::MatrixXd::Ones(3, 1), Eigen::MatrixXd::Ones(2, 1)), std::invalid_argument);
}

TEST(MpcQp, RejectsInconsistentSizes) {
  EXPECT_THROW(random_data(3, 2, 4, 5, 1), std::invalid_argument);  // M > N
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(2, 2);
  EXPECT_THROW(build_mpc_qp(A, Eigen::MatrixXd::Ones(3, 1), A, Eigen::MatrixXd::Ones(1, 1), A,
                            Box::symmetric(Eigen::VectorXd::Ones(2)), Box::symmetric(Eigen::VectorXd::Ones(1)), 3, 2),
               std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
