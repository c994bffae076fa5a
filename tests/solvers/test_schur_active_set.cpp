// The active-set finish of the exact ADMM (src/solvers/schur_active_set.hpp) on random
// strictly convex QPs, from good, rough and nonsensical guesses: its point against the
// KKT conditions (kkt.hpp, written from the definition) and the reference solver's
// objective; dependent and repeated rows, an infeasible instance, the step cap.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "schur_active_set.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {
namespace {

using detail::SchurActiveSet;

/// A random strictly convex QP with m rows around a feasible point; `dup` rows repeat
/// earlier rows (dependent, same bounds) and `eq` rows are equalities.
CondensedQp random_qp(std::mt19937_64& rng, int n, int m, int dup, int eq) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.05, 1.0);
  CondensedQp qp;
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = g(rng);
  qp.H = M * M.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  qp.f.resize(n);
  for (int i = 0; i < n; ++i) qp.f(i) = 10.0 * g(rng);  // pushes the minimizer out of the set
  qp.A.resize(m, n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) qp.A(i, j) = g(rng);
  for (int k = 0; k < dup; ++k) qp.A.row(m - 1 - k) = qp.A.row(k);
  Eigen::VectorXd x0(n);
  for (int i = 0; i < n; ++i) x0(i) = 0.1 * g(rng);
  const Eigen::VectorXd Ax0 = qp.A * x0;
  qp.lo = Ax0.array() - Eigen::VectorXd::NullaryExpr(m, [&] { return u(rng); }).array();
  qp.hi = Ax0.array() + Eigen::VectorXd::NullaryExpr(m, [&] { return u(rng); }).array();
  for (int k = 0; k < dup; ++k) {
    qp.lo(m - 1 - k) = qp.lo(k);
    qp.hi(m - 1 - k) = qp.hi(k);
  }
  for (int k = 0; k < eq; ++k) qp.lo(dup + k) = qp.hi(dup + k) = Ax0(dup + k);
  return qp;
}

double reference_objective(const CondensedQp& qp) {
  ParametricQp p;
  p.H = qp.H;
  p.f0 = qp.f;
  p.F = Eigen::MatrixXd::Zero(qp.H.rows(), 1);
  p.A = qp.A;
  p.E = Eigen::MatrixXd::Zero(qp.A.rows(), 1);
  p.lo0 = qp.lo;
  p.hi0 = qp.hi;
  auto ref = make_reference_solver(p);
  const SolveResult r = ref->solve(Eigen::VectorXd::Zero(1));
  EXPECT_EQ(r.status, SolveStatus::Converged);
  return r.objective;
}

TEST(SchurActiveSet, ReachesTheOptimumFromAnyGuess) {
  std::mt19937_64 rng(5);
  int cases = 0, max_steps = 0;
  double worst_kkt = 0.0, worst_gap = 0.0;
  for (int t = 0; t < 60; ++t) {
    const int n = 12, m = 30;
    const CondensedQp qp = random_qp(rng, n, m, t % 3 == 0 ? 4 : 0, t % 4 == 0 ? 2 : 0);
    const double ref = reference_objective(qp);
    SchurActiveSet s;  // A z through G = A H^-1 A' (odd cases) or formed directly
    ASSERT_TRUE(s.setup(qp.H, qp.A, t % 2 == 1 ? 2'500'000 : 0));
    // Guesses: none; every row at its upper bound; random rows and sides; the true
    // active set (from the empty guess's answer) with spurious rows in front.
    Eigen::VectorXd z(n), y(m);
    s.clear();
    ASSERT_TRUE(s.solve(qp.f, qp.lo, qp.hi, 1e-9, 200, z, y)) << "empty guess, case " << t;
    const Eigen::VectorXd y_true = y;
    for (int guess = 0; guess < 4; ++guess) {
      s.clear();
      std::uniform_int_distribution<int> row(0, m - 1);
      if (guess == 1)
        for (int i = 0; i < m; ++i) s.propose(i, true);
      if (guess == 2)
        for (int k = 0; k < 8; ++k) s.propose(row(rng), rng() % 2 == 0);
      if (guess == 3) {
        for (int k = 0; k < 3; ++k) s.propose(row(rng), rng() % 2 == 0);
        for (int i = 0; i < m; ++i)
          if (y_true(i) != 0.0) s.propose(i, y_true(i) > 0.0);
      }
      ASSERT_TRUE(s.solve(qp.f, qp.lo, qp.hi, 1e-9, 200, z, y)) << "guess " << guess << ", case " << t;
      const KktResiduals k = kkt_residuals(qp, z, y);
      worst_kkt = std::max(worst_kkt, k.max() / std::max(1.0, qp.f.cwiseAbs().maxCoeff()));
      const double obj = 0.5 * z.dot(qp.H * z) + qp.f.dot(z);
      worst_gap = std::max(worst_gap, std::abs(obj - ref) / std::max(1.0, std::abs(ref)));
      max_steps = std::max(max_steps, s.steps());
      ++cases;
    }
  }
  std::printf("%d finishes: worst relative KKT residual %.2e, objective gap to the reference %.2e, at most %d steps\n",
              cases, worst_kkt, worst_gap, max_steps);
  EXPECT_LT(worst_kkt, 1e-8);
  EXPECT_LT(worst_gap, 1e-9);
}

TEST(SchurActiveSet, RepeatedRowsAtTheOptimumAreTakenOnce) {
  // min 1/2 |z|^2 - 10 z_0 s.t. z_0 <= 1 (three times, one as 2 z_0 <= 2), z_1 >= -1.
  CondensedQp qp;
  qp.H = Eigen::MatrixXd::Identity(2, 2);
  qp.f = Eigen::Vector2d(-10.0, 0.0);
  qp.A.resize(4, 2);
  qp.A << 1, 0, 1, 0, 2, 0, 0, 1;
  qp.lo = Eigen::Vector4d(-5, -5, -10, -1);
  qp.hi = Eigen::Vector4d(1, 1, 2, 1);
  SchurActiveSet s;
  ASSERT_TRUE(s.setup(qp.H, qp.A));
  for (int r : {0, 1, 2}) s.propose(r, true);
  Eigen::VectorXd z(2), y(4);
  ASSERT_TRUE(s.solve(qp.f, qp.lo, qp.hi, 1e-9, 10, z, y));
  EXPECT_NEAR(z(0), 1.0, 1e-12);
  EXPECT_NEAR(z(1), 0.0, 1e-12);
  EXPECT_EQ((y.array() != 0.0).count(), 1) << "one of the three parallel rows carries the multiplier";
  EXPECT_LT(kkt_residuals(qp, z, y).max(), 1e-12);
}

TEST(SchurActiveSet, FailsWithoutTouchingItsOutputs) {
  CondensedQp qp;
  qp.H = Eigen::MatrixXd::Identity(2, 2);
  qp.f = Eigen::Vector2d(-10.0, 0.0);
  qp.A.resize(2, 2);
  qp.A << 1, 0, -1, 0;  // z_0 <= 1 and -z_0 <= -2: no point
  qp.lo = Eigen::Vector2d(-5, -5);
  qp.hi = Eigen::Vector2d(1, -2);
  SchurActiveSet s;
  ASSERT_TRUE(s.setup(qp.H, qp.A));
  Eigen::VectorXd z = Eigen::Vector2d(7, 7), y = Eigen::Vector2d(7, 7);
  EXPECT_FALSE(s.solve(qp.f, qp.lo, qp.hi, 1e-9, 50, z, y)) << "infeasible";
  EXPECT_EQ(z, Eigen::Vector2d(7, 7));
  EXPECT_EQ(y, Eigen::Vector2d(7, 7));
  // A feasible instance and a wrong guess, but no step allowed.
  qp.hi(1) = 5.0;
  s.clear();
  s.propose(1, false);
  EXPECT_FALSE(s.solve(qp.f, qp.lo, qp.hi, 1e-9, 0, z, y)) << "step cap";
  EXPECT_EQ(z, Eigen::Vector2d(7, 7));
  EXPECT_TRUE(s.solve(qp.f, qp.lo, qp.hi, 1e-9, 5, z, y));
  EXPECT_NEAR(z(0), 1.0, 1e-12);
  // A singular H (the CZ form): not usable.
  SchurActiveSet singular;
  EXPECT_FALSE(singular.setup(Eigen::MatrixXd::Zero(2, 2), qp.A));
  EXPECT_FALSE(singular.ready());
}

}  // namespace
}  // namespace tmpc
