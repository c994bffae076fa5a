// Point location: scan (1, 2 threads) and search tree return the same region, the one
// that contains the point, on a double-integrator partition; ties on shared facets
// go to the same (lowest-index) region; points outside the domain are reported.
#include <random>

#include <gtest/gtest.h>

#include "tmpc/explicit/point_location.hpp"
#include "tmpc/qp/mpc_qp.hpp"

namespace tmpc {
namespace {

Partition double_integrator_partition() {
  Eigen::Matrix2d A;
  A << 1, 1, 0, 1;
  const MpcQpData d = build_mpc_qp(A, Eigen::Vector2d(0.5, 1.0), Eigen::Matrix2d::Identity(),
                                   0.1 * Eigen::MatrixXd::Identity(1, 1), Eigen::Matrix2d::Identity(),
                                   Box(Eigen::Vector2d(-10, -2), Eigen::Vector2d(10, 2)),
                                   Box(Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Constant(1, 1.0)), 5, 5);
  return solve_mpqp(MpQp::from_parametric(ParametricQp::from_mpc(d), Box(Eigen::Vector2d(-8, -2), Eigen::Vector2d(8, 2))));
}

TEST(PointLocation, ScanAndTreeAgreeEverywhereAndOnSharedFacets) {
  const Partition p = double_integrator_partition();
  ASSERT_TRUE(p.stats.complete);
  ASSERT_GT(p.regions.size(), 10u);
  const RegionTable t = RegionTable::from(p.regions);
  const SearchTree tree = SearchTree::build(p.regions, p.domain);
  EXPECT_GT(tree.stats.depth, 1);
  const RegionScan s1(t, 1), s2(t, 2);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ux(-8.0, 8.0), uv(-2.0, 2.0);
  for (int k = 0; k < 100000; ++k) {
    const Eigen::Vector2d th(ux(rng), uv(rng));
    const int r = s1.locate(th);
    ASSERT_EQ(s2.locate(th), r);
    ASSERT_EQ(tree.locate(t, th), r);
    if (r >= 0) ASSERT_TRUE(p.regions[static_cast<std::size_t>(r)].set.contains(th, kLocateTolerance));
    ASSERT_EQ(r, p.locate(th));
  }
  // Points on shared facets: the midpoint of each region's facets, both methods pick
  // the lowest-index region containing it.
  int ties = 0;
  for (const CriticalRegion& cr : p.regions) {
    for (Eigen::Index i = 0; i < cr.set.H.rows(); ++i) {
      // Project the Chebyshev center onto facet i.
      const Eigen::Vector2d a = cr.set.H.row(i).transpose();
      const Eigen::Vector2d on = cr.center - (a.dot(cr.center) - cr.set.k(i)) * a;
      const int r = s1.locate(on);
      if (r < 0) continue;
      ++ties;
      EXPECT_EQ(tree.locate(t, on), r);
      EXPECT_EQ(s2.locate(on), r);
    }
  }
  EXPECT_GT(ties, 20);
  EXPECT_EQ(s1.locate(Eigen::Vector2d(9.0, 0.0)), -1);
  EXPECT_EQ(tree.locate(t, Eigen::Vector2d(9.0, 0.0)), -1);
  EXPECT_EQ(tree.locate(t, Eigen::Vector3d(0.0, 0.0, 0.0)), -1);  // wrong size: not a crash
}

}  // namespace
}  // namespace tmpc
