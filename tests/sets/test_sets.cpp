// Set operations against brute force: zonotope support by vertex enumeration,
// Pontryagin differences by sampling (sound) and by witnesses (not conservative),
// H-polytope to constrained zonotope by membership.
#include <random>

#include <gtest/gtest.h>

#include "tmpc/sets/box.hpp"
#include "tmpc/sets/constrained_zonotope.hpp"
#include "tmpc/sets/hpolytope.hpp"
#include "tmpc/sets/zonotope.hpp"

namespace tmpc {
namespace {

Zonotope random_zonotope(std::mt19937_64& rng, int n, int r, double scale) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::VectorXd c(n);
  Eigen::MatrixXd G(n, r);
  for (int i = 0; i < n; ++i) c(i) = 0.1 * scale * g(rng);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < r; ++j) G(i, j) = scale * g(rng);
  return Zonotope(c, G);
}

TEST(Zonotope, SupportEqualsTheMaximumOverAllVertices) {
  std::mt19937_64 rng(1);
  for (int t = 0; t < 20; ++t) {
    const Zonotope z = random_zonotope(rng, 3, 6, 1.0);
    const Eigen::VectorXd d = Eigen::VectorXd::Random(3);
    double best = -1e300;
    for (int mask = 0; mask < (1 << 6); ++mask) {
      Eigen::VectorXd xi(6);
      for (int j = 0; j < 6; ++j) xi(j) = (mask >> j) & 1 ? 1.0 : -1.0;
      best = std::max(best, d.dot(z.c + z.G * xi));
    }
    EXPECT_NEAR(z.support(d), best, 1e-12);
    EXPECT_NEAR(z.map(Eigen::MatrixXd::Identity(3, 3) * 2.0).support(d), 2.0 * best, 1e-12);
  }
}

TEST(Box, PontryaginDifferenceIsExactForRandomBoxesAndZonotopes) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int t = 0; t < 50; ++t) {
    const int n = 4;
    Eigen::VectorXd lo(n), hi(n);
    for (int i = 0; i < n; ++i) {
      lo(i) = -1.0 - u(rng);
      hi(i) = 1.0 + u(rng);
    }
    const Box X(lo, hi);
    const Zonotope Z = random_zonotope(rng, n, 5, 0.1);
    const Box Xb = X.minus(Z);
    ASSERT_FALSE(Xb.empty());
    // Sound: every x in X_bar plus every z in Z lies in X (vertices of Z and random points).
    for (int k = 0; k < 200; ++k) {
      Eigen::VectorXd x = Xb.lo + (Xb.hi - Xb.lo).cwiseProduct((Eigen::VectorXd::Random(n).array() + 1.0).matrix() / 2.0);
      Eigen::VectorXd xi = Eigen::VectorXd::Random(5);
      if (k % 2 == 0) xi = xi.array().sign();
      EXPECT_TRUE(X.contains(x + Z.c + Z.G * xi, 1e-12));
    }
    // Support functions agree: h_X(d) >= h_Xbar(d) + h_Z(d) with equality on the axes.
    for (int i = 0; i < n; ++i) {
      Eigen::VectorXd e = Eigen::VectorXd::Unit(n, i);
      EXPECT_NEAR(Xb.support(e) + Z.support(e), X.support(e), 1e-12);
      EXPECT_NEAR(Xb.support(-e) + Z.support(-e), X.support(-e), 1e-12);
    }
    // Not conservative: a point just outside a face of X_bar plus the z that is
    // extreme in that direction leaves X.
    for (int i = 0; i < n; ++i) {
      Eigen::VectorXd x = Xb.center();
      x(i) = Xb.hi(i) + 1e-9;
      const Eigen::VectorXd xi = Z.G.row(i).transpose().array().sign();
      EXPECT_FALSE(X.contains(x + Z.c + Z.G * xi));
    }
  }
}

TEST(HPolytope, PontryaginDifferenceIsSoundAndTight) {
  std::mt19937_64 rng(3);
  for (int t = 0; t < 20; ++t) {
    const int n = 3, rows = 10;
    Eigen::MatrixXd H = Eigen::MatrixXd::Random(rows, n);
    for (int i = 0; i < rows; ++i) H.row(i).normalize();
    const HPolytope P(H, Eigen::VectorXd::Ones(rows));
    const Zonotope Z = random_zonotope(rng, n, 4, 0.05);
    const HPolytope Pb = P.minus(Z);
    int inside = 0;
    for (int k = 0; k < 2000 && inside < 100; ++k) {
      const Eigen::VectorXd x = 2.0 * Eigen::VectorXd::Random(n);
      if (!Pb.contains(x)) continue;
      ++inside;
      for (int v = 0; v < 16; ++v) {
        Eigen::VectorXd xi(4);
        for (int j = 0; j < 4; ++j) xi(j) = (v >> j) & 1 ? 1.0 : -1.0;
        EXPECT_TRUE(P.contains(x + Z.c + Z.G * xi, 1e-12));
      }
    }
    EXPECT_GT(inside, 10);
    // Tight: offsets equal k_i - h_Z(h_i).
    for (int i = 0; i < rows; ++i) EXPECT_NEAR(Pb.k(i), 1.0 - Z.support(H.row(i).transpose()), 1e-12);
  }
}

TEST(ConstrainedZonotope, FromHPolytopeRepresentsTheSameSet) {
  std::mt19937_64 rng(4);
  const int n = 3, rows = 8;
  Eigen::MatrixXd H = Eigen::MatrixXd::Random(rows, n);
  for (int i = 0; i < rows; ++i) H.row(i).normalize();
  const HPolytope P(H, 0.5 * Eigen::VectorXd::Ones(rows));
  const Box bound = Box::symmetric(Eigen::VectorXd::Constant(n, 2.0));
  const ConstrainedZonotope cz = ConstrainedZonotope::from_hpolytope(P, bound);
  EXPECT_EQ(cz.generators(), n + rows);
  EXPECT_EQ(cz.constraints(), rows);
  // For x in the bounding box, xi = G0^-1 (x - c) is fixed and the slack factors are
  // determined by A xi = b: x is in the CZ iff they lie in [-1, 1].
  int agree = 0;
  for (int k = 0; k < 5000; ++k) {
    const Eigen::VectorXd x = 2.0 * Eigen::VectorXd::Random(n);
    Eigen::VectorXd xi(n + rows);
    xi.head(n) = cz.G.leftCols(n).diagonal().cwiseInverse().cwiseProduct(x - cz.c);
    const Eigen::VectorXd rhs = cz.b - cz.A.leftCols(n) * xi.head(n);
    xi.tail(rows) = rhs.cwiseQuotient(cz.A.rightCols(rows).diagonal());
    const bool in_cz = (xi.cwiseAbs().array() <= 1.0 + 1e-12).all();
    EXPECT_EQ(in_cz, P.contains(x, 1e-12)) << x.transpose();
    EXPECT_LT((cz.point(xi) - x).norm(), 1e-12);
    agree += in_cz;
  }
  EXPECT_GT(agree, 50);
  // Boxes stay constraint-free.
  EXPECT_EQ(ConstrainedZonotope::from_box(bound).constraints(), 0);
}

}  // namespace
}  // namespace tmpc
