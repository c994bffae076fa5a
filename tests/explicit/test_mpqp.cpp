// mpQP partitions on textbook problems with known answers, degenerate ones included,
// checked against the reference QP solver (an independent code path: interior point).
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "tmpc/explicit/mpqp.hpp"
#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// min 1/2 (z - th)^2 s.t. -1 <= z <= 1, th in [-2, 2], plus redundant copies of the
// upper bound: a duplicate, a scaled duplicate (2 z <= 2) and a slack one (z <= 1.5).
ParametricQp saturation_1d(bool redundant) {
  ParametricQp q;
  q.H = Eigen::MatrixXd::Identity(1, 1);
  q.F = -Eigen::MatrixXd::Identity(1, 1);
  q.f0 = Eigen::VectorXd::Zero(1);
  const int rows = redundant ? 4 : 1;
  q.A.resize(rows, 1);
  q.lo0 = Eigen::VectorXd::Constant(rows, -kInf);
  q.hi0.resize(rows);
  q.A(0, 0) = 1.0;
  q.lo0(0) = -1.0;
  q.hi0(0) = 1.0;
  if (redundant) {
    q.A(1, 0) = 1.0;
    q.hi0(1) = 1.0;
    q.A(2, 0) = 2.0;
    q.hi0(2) = 2.0;
    q.A(3, 0) = 1.0;
    q.hi0(3) = 1.5;
  }
  q.E = Eigen::MatrixXd::Zero(rows, 1);
  return q;
}

TEST(MpQp, SaturationHasThreeRegionsWithTheKnownLaws) {
  for (bool redundant : {false, true}) {
    const Partition part = solve_mpqp(MpQp::from_parametric(saturation_1d(redundant), Box(Eigen::VectorXd::Constant(1, -2.0), Eigen::VectorXd::Constant(1, 2.0))));
    ASSERT_TRUE(part.stats.complete) << part.stats.stop_reason;
    ASSERT_EQ(part.regions.size(), 3u) << "redundant=" << redundant;
    for (double th = -1.99; th < 2.0; th += 0.01) {
      const int r = part.locate(Eigen::VectorXd::Constant(1, th));
      ASSERT_GE(r, 0) << th;
      EXPECT_NEAR(part.regions[static_cast<std::size_t>(r)].z(Eigen::VectorXd::Constant(1, th))(0), std::clamp(th, -1.0, 1.0), 1e-12);
    }
  }
}

// min 1/2 (z - 1)^2 s.t. z <= th1, z <= th2: z = min(1, th1, th2). The active set
// {both} is linearly dependent and its region is the half-line th1 = th2 <= 1, of lower
// dimension: the partition is the three full-dimensional regions.
TEST(MpQp, LowerDimensionalRegionAndDependentActiveSetAreHandled) {
  ParametricQp q;
  q.H = Eigen::MatrixXd::Identity(1, 1);
  q.F = Eigen::MatrixXd::Zero(1, 2);
  q.f0 = Eigen::VectorXd::Constant(1, -1.0);
  q.A = Eigen::MatrixXd::Ones(2, 1);
  q.E = -Eigen::MatrixXd::Identity(2, 2);  // z <= th_i  <=>  A z <= 0 - E th
  q.hi0 = Eigen::VectorXd::Zero(2);
  q.lo0 = Eigen::VectorXd::Constant(2, -kInf);
  const Partition part = solve_mpqp(MpQp::from_parametric(q, Box(Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2))));
  ASSERT_TRUE(part.stats.complete) << part.stats.stop_reason;
  EXPECT_EQ(part.regions.size(), 3u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector2d th(u(rng), u(rng));
    const int r = part.locate(th);
    ASSERT_GE(r, 0);
    EXPECT_NEAR(part.regions[static_cast<std::size_t>(r)].z(th)(0), std::min({1.0, th(0), th(1)}), 1e-12);
  }
  // Points on the lower-dimensional set are covered by the closures of its neighbours.
  EXPECT_GE(part.locate(Eigen::Vector2d(0.3, 0.3)), 0);
}

// The double integrator with input and state boxes; the same problem with every
// constraint row duplicated and a scaled copy gives the same partition.
MpcQpData double_integrator(int N) {
  Eigen::Matrix2d A;
  A << 1, 1, 0, 1;
  Eigen::Vector2d B(0.5, 1.0);
  const Eigen::Matrix2d Q = Eigen::Matrix2d::Identity();
  const Eigen::MatrixXd R = 0.1 * Eigen::MatrixXd::Identity(1, 1);
  return build_mpc_qp(A, B, Q, R, Q, Box(Eigen::Vector2d(-10, -2), Eigen::Vector2d(10, 2)),
                      Box(Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Constant(1, 1.0)), N, N);
}

ParametricQp with_redundant_rows(const ParametricQp& q) {
  ParametricQp r = q;
  const Eigen::Index nc = q.nc();
  r.A.resize(3 * nc, q.nz());
  r.E.resize(3 * nc, q.nx());
  r.lo0.resize(3 * nc);
  r.hi0.resize(3 * nc);
  r.A << q.A, q.A, 3.0 * q.A;
  r.E << q.E, q.E, 3.0 * q.E;
  r.lo0 << q.lo0, q.lo0, 3.0 * q.lo0;
  r.hi0 << q.hi0, q.hi0, 3.0 * q.hi0;
  return r;
}

void expect_matches_reference(const Partition& part, const ParametricQp& q, int samples, unsigned seed) {
  auto ref = make_reference_solver(q);
  const MpQp mp = MpQp::from_parametric(q, part.domain);
  std::mt19937 rng(seed);
  int inside = 0;
  for (int k = 0; k < samples; ++k) {
    Eigen::VectorXd th(q.nx());
    for (int j = 0; j < th.size(); ++j) {
      th(j) = std::uniform_real_distribution<double>(part.domain.lo(j), part.domain.hi(j))(rng);
    }
    const int r = part.locate(th);
    const bool feasible = mpqp_feasible(mp, th);
    ASSERT_EQ(r >= 0, feasible) << "coverage: sample " << k << " feasible=" << feasible;
    if (r < 0) continue;
    ++inside;
    const SolveResult& s = ref->solve(th);
    ASSERT_EQ(s.status, SolveStatus::Converged) << "sample " << k << " th " << th.transpose() << " it " << s.iterations << " pres " << s.primal_residual << " dres " << s.dual_residual;
    EXPECT_LE((part.regions[static_cast<std::size_t>(r)].z(th) - s.z).cwiseAbs().maxCoeff(), 1e-6) << "sample " << k;
  }
  EXPECT_GT(inside, samples / 10);
}

TEST(MpQp, DoubleIntegratorMatchesTheReferenceAndIgnoresRedundantRows) {
  const ParametricQp q = ParametricQp::from_mpc(double_integrator(3));
  const Box dom(Eigen::Vector2d(-8, -2), Eigen::Vector2d(8, 2));
  const Partition plain = solve_mpqp(MpQp::from_parametric(q, dom));
  const Partition redundant = solve_mpqp(MpQp::from_parametric(with_redundant_rows(q), dom));
  ASSERT_TRUE(plain.stats.complete) << plain.stats.stop_reason;
  ASSERT_TRUE(redundant.stats.complete) << redundant.stats.stop_reason;
  EXPECT_GT(plain.regions.size(), 5u);
  EXPECT_EQ(plain.regions.size(), redundant.regions.size());
  expect_matches_reference(plain, q, 20000, 5);
  expect_matches_reference(redundant, with_redundant_rows(q), 5000, 6);
}

TEST(MpQp, SaysWhenItGivesUp) {
  const ParametricQp q = ParametricQp::from_mpc(double_integrator(3));
  MpQpOptions o;
  o.max_regions = 3;
  const Partition part = solve_mpqp(MpQp::from_parametric(q, Box(Eigen::Vector2d(-8, -2), Eigen::Vector2d(8, 2))), o);
  EXPECT_FALSE(part.stats.complete);
  EXPECT_EQ(part.regions.size(), 3u);
  EXPECT_NE(part.stats.stop_reason.find("region limit 3"), std::string::npos) << part.stats.stop_reason;
  o.max_regions = 0;
  EXPECT_THROW(solve_mpqp(MpQp::from_parametric(q, Box(Eigen::Vector2d(-8, -2), Eigen::Vector2d(8, 2))), o),
               std::invalid_argument);
}

TEST(MpQp, BadInputIsRejectedWithTheReason) {
  ParametricQp q = saturation_1d(false);
  q.H(0, 0) = -1.0;
  try {
    MpQp::from_parametric(q, Box(Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Constant(1, 1.0)));
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("positive definite"), std::string::npos);
  }
  EXPECT_THROW(MpQp::from_parametric(saturation_1d(false), Box(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1))),
               std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
