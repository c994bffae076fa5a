// The yaw governor (runtime/yaw_governor.hpp): the reference's yaw turned so that the
// force on the load lies on the box's diagonal in the load's yaw frame. The oracle is
// the geometry: after the turn the force's components in the turned frame stand in the
// ratio of the phi and theta bounds, computed here from the world force directly.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/runtime/yaw_governor.hpp"

namespace tmpc {
namespace {

YawGovernorSettings settings(double phi_bound = 0.5, double theta_bound = 0.5) {
  YawGovernorSettings s;
  s.rate_max = 0.15;
  s.acceleration_max = 0.2;
  s.force_on = 0.75;
  s.phi_bound = phi_bound;
  s.theta_bound = theta_bound;
  return s;
}

/// The world force seen from the frame turned by psi.
Eigen::Vector2d in_frame(const Eigen::Vector2d& F, double psi) {
  return {std::cos(psi) * F.x() + std::sin(psi) * F.y(), -std::sin(psi) * F.x() + std::cos(psi) * F.y()};
}

/// Fly the governor `seconds` against a steady world force; return the largest |rate|
/// and |acceleration| seen. The estimate arrives in the governed frame, as the
/// controller's does.
Eigen::Vector2d fly(YawGovernor& g, const Eigen::Vector2d& F, double psi_mission, double seconds) {
  const double dt = 0.012;
  Eigen::Vector2d peak = Eigen::Vector2d::Zero();
  for (int k = 0; k * dt < seconds; ++k) {
    const double psi = psi_mission + g.offset();
    g.update(in_frame(F, psi), psi, psi_mission, dt);
    peak = peak.cwiseMax(Eigen::Vector2d(std::abs(g.rate()), std::abs(g.acceleration())));
  }
  return peak;
}

TEST(YawGovernor, TurnsTheForceOntoTheBoxsDiagonalWithinItsRateAndAcceleration) {
  for (double mission : {0.0, 1.0, -2.5}) {
    for (double dir : {0.0, 0.4, 2.0, -1.2}) {
      YawGovernor g(settings());
      const Eigen::Vector2d F = 2.0 * Eigen::Vector2d(std::cos(dir), std::sin(dir));
      const Eigen::Vector2d peak = fly(g, F, mission, 30.0);
      const Eigen::Vector2d f = in_frame(F, mission + g.offset());
      EXPECT_NEAR(std::abs(f.x()), std::abs(f.y()), 1e-3) << mission << " " << dir;  // on a diagonal
      EXPECT_LE(std::abs(g.offset()), M_PI / 4 + 1e-3) << "the diagonal nearest the mission's yaw";
      EXPECT_LE(peak(0), 0.15 + 1e-12);
      EXPECT_LE(peak(1), 0.2 + 1e-9);
      EXPECT_NEAR(g.rate(), 0.0, 1e-2);
    }
  }
}

TEST(YawGovernor, UnequalBoundsSplitTheForceInTheirRatio) {
  YawGovernor g(settings(0.3, 0.6));  // phi bound half theta's
  const Eigen::Vector2d F(1.5, 0.2);
  fly(g, F, 0.0, 40.0);
  const Eigen::Vector2d f = in_frame(F, g.offset());
  // phi bears the component across (y), theta the one along (x): |f_y| / 0.3 = |f_x| / 0.6.
  EXPECT_NEAR(std::abs(f.y()) / 0.3, std::abs(f.x()) / 0.6, 1e-2);
}

TEST(YawGovernor, AForceBelowItsThresholdTurnsNothingAndAFadingOneTurnsBack) {
  YawGovernor g(settings());
  fly(g, Eigen::Vector2d(0.7, 0.1), 0.3, 10.0);  // larger component 0.7 < 0.75 at the mission's yaw
  EXPECT_FALSE(g.active());
  EXPECT_EQ(g.offset(), 0.0);
  fly(g, Eigen::Vector2d(2.0, 0.0), 0.3, 20.0);
  EXPECT_TRUE(g.active());
  EXPECT_GT(std::abs(g.offset()), 0.3);
  fly(g, Eigen::Vector2d(0.65, 0.0), 0.3, 20.0);  // above 0.8 of the threshold: held
  EXPECT_TRUE(g.active());
  fly(g, Eigen::Vector2d(0.5, 0.0), 0.3, 30.0);  // below: back to the mission's yaw
  EXPECT_FALSE(g.active());
  EXPECT_NEAR(g.offset(), 0.0, 1e-2);
  // A non-finite estimate moves nothing.
  const double before = g.offset();
  g.update(Eigen::Vector2d(NAN, 0.0), 0.3, 0.3, 0.012);
  EXPECT_EQ(g.offset(), before);
}

TEST(YawGovernor, TheGovernedTrajectoryCarriesTheOffsetAndItsDerivatives) {
  YawGovernor g(settings());
  fly(g, Eigen::Vector2d(2.0, 0.0), 0.0, 1.0);  // mid-turn: rate and acceleration nonzero
  ASSERT_NE(g.rate(), 0.0);
  const auto base = std::shared_ptr<const Trajectory>(make_hover({Eigen::Vector3d(0, 0, 2), 0.0}));
  const GovernedTrajectory t(base, &g);
  const TrajectoryPoint p = t.at(3.0), q = base->at(3.0);
  EXPECT_EQ(p.p, q.p);
  EXPECT_DOUBLE_EQ(p.psi, q.psi + g.offset());
  EXPECT_DOUBLE_EQ(p.psi_d, q.psi_d + g.rate());
  EXPECT_DOUBLE_EQ(p.psi_dd, q.psi_dd + g.acceleration());
}

TEST(YawGovernor, SettingsFromTheArtifactAndTheTrajectory) {
  const ControllerArtifact a = test::quick_artifact();
  const auto helix = make_helix({Eigen::Vector3d(0, 0, 4), 5.0, 3.0, M_PI / 40, 0.0});
  YawGovernorSettings s = yaw_governor_settings(a, *helix, 80.0);
  EXPECT_DOUBLE_EQ(s.rate_max, 0.2 - 0.01);  // the helix does not turn
  EXPECT_DOUBLE_EQ(s.acceleration_max, 0.2);
  EXPECT_DOUBLE_EQ(s.phi_bound, 0.5);
  EXPECT_DOUBLE_EQ(s.theta_bound, 0.5);
  // 0.3 of the 0.5 rad bound under the 0.5 kg load's weight.
  EXPECT_NEAR(s.force_on, std::tan(0.15) * 0.5 * 9.81, 1e-12);
  // The trajectory's own turn takes its share of the envelope's rate.
  std::string csv = "t,x,y,z,psi\n";
  for (int k = 0; k <= 50; ++k) csv += std::to_string(0.1 * k) + ",0,0,2," + std::to_string(0.15 * 0.1 * k) + "\n";
  s = yaw_governor_settings(a, *make_csv_trajectory(csv, "turn.csv"), 4.0);
  EXPECT_NEAR(s.rate_max, 0.2 - 0.15 - 0.01, 1e-3);
  csv = "t,x,y,z,psi\n";
  for (int k = 0; k <= 50; ++k) csv += std::to_string(0.1 * k) + ",0,0,2," + std::to_string(0.195 * 0.1 * k) + "\n";
  EXPECT_THROW(yaw_governor_settings(a, *make_csv_trajectory(csv, "fast.csv"), 4.0), std::invalid_argument);
  ControllerArtifact fixed = a;
  fixed.envelope.yaw_rate_max = -1.0;
  EXPECT_THROW(yaw_governor_settings(fixed, *helix, 80.0), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
