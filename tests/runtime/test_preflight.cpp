// Pre-flight: a trajectory inside the artifact's envelope is flyable; one that leaves
// it is refused with the first time and the numbers, the time checked against the
// trajectory's closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/runtime/preflight.hpp"

namespace tmpc {
namespace {

const ControllerArtifact& artifact() {
  static const ControllerArtifact a = test::quick_artifact();
  return a;
}

TEST(Preflight, TheShippedTrajectoriesAreInsideTheDefaultEnvelope) {
  // Every tiltrotor scenario shipped (the others fly the helix: the gusts, noise, force
  // and mass scenarios check the same trajectory, once).
  for (const char* name : {"thesis_helix", "figure_eight", "waypoints", "lissajous_csv"}) {
    const Scenario s = test::shipped_scenario(name);
    const PreflightReport r = check_flight(artifact(), *s.trajectory, s.duration);
    EXPECT_TRUE(r.ok) << name << ": " << r.message;
    EXPECT_NE(r.message.find("inside the envelope"), std::string::npos) << r.message;
    for (int i = 0; i < 4; ++i) {  // the feedforward stayed in the range the inputs were tightened for
      EXPECT_GE(r.feedforward_min(i), artifact().feedforward_min(i) - 1e-6) << name;
      EXPECT_LE(r.feedforward_max(i), artifact().feedforward_max(i) + 1e-6) << name;
    }
  }
  for (const char* name : {"gusts", "noisy_sensors", "sustained_force", "masses_30", "noisy_sensors_x2", "gusts_2n",
                           "sustained_force_4n"}) {
    EXPECT_EQ(test::shipped_scenario(name).trajectory->description(),
              test::shipped_scenario("thesis_helix").trajectory->description()) << name;
  }
}

TEST(Preflight, AFastFigureEightIsRefusedAtTheFirstPeriodOutside) {
  // a_y = -2 ay w^2 sin(2 w t): with ay = 3 m, w = 0.3 rad/s its peak is 0.54 m/s^2;
  // it first leaves the envelope's 0.06 m/s^2 at sin(2 w t) = 0.06 / 0.54 (its speed,
  // at most 0.95 m/s, stays inside; a_x leaves later).
  const double w = 0.3, ay = 3.0;
  const auto eight = make_figure_eight({Eigen::Vector3d(0, 0, 3), Eigen::Vector2d(1, ay), w, 0.0});
  const PreflightReport r = check_flight(artifact(), *eight, 60.0);
  ASSERT_FALSE(r.ok);
  const double limit = artifact().envelope.acceleration_max.y();
  const double t_exit = std::asin(limit / (2 * ay * w * w)) / (2 * w);
  const double T = artifact().sample_time;
  EXPECT_GT(r.time, t_exit - 1e-9);
  EXPECT_LE(r.time, t_exit + T);
  EXPECT_NE(r.message.find("acceleration y = -0.06"), std::string::npos) << r.message;  // a_y < 0 first
  EXPECT_GT(r.speed_max, 0.9);  // the report's range covers the flight up to the refusal
  EXPECT_NE(r.message.find("outside the envelope [-0.06, 0.06]"), std::string::npos) << r.message;
}

TEST(Preflight, SpeedYawAndTheLinearModelsOrigin) {
  // A wide circle: 1.125 m/s, above the envelope's 1 m/s, at 0.051 m/s^2.
  const auto wide = make_circle({Eigen::Vector3d(0, 0, 4), 25.0, 0.045, 0.0});
  PreflightReport r = check_flight(artifact(), *wide, 80.0);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.message.find("t = 0 s: speed 1.125 m/s above the envelope's 1 m/s"), std::string::npos) << r.message;
  // The helix at twice the thesis' rate: 0.12 m/s^2 along x at t = 0.
  const auto fast = make_helix({Eigen::Vector3d(0, 0, 4), 5.0, 3.0, 2 * M_PI / 40.0, 0.0});
  r = check_flight(artifact(), *fast, 80.0);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.message.find("t = 0 s: acceleration x = -0.12"), std::string::npos) << r.message;
  // A fixed-yaw design (yaw_tolerance): a yaw beyond its tolerance (0 +- 0.05 rad).
  ControllerArtifact fixed = artifact();
  fixed.envelope.yaw_rate_max = -1.0;
  fixed.envelope.yaw_tolerance = 0.05;
  const auto turned = make_hover({Eigen::Vector3d(0, 0, 2), 0.3});
  r = check_flight(fixed, *turned, 5.0);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.message.find("yaw 0.3 rad outside the envelope's 0 +- 0.05 rad"), std::string::npos) << r.message;
  EXPECT_THROW(require_flight(fixed, *turned, 5.0, "test"), std::invalid_argument);
}

TEST(Preflight, AnAnyYawDesignFliesEveryYawAtItsRateWithTheBoxInTheYawFrame) {
  ASSERT_TRUE(artifact().envelope.any_yaw());
  // Any constant yaw: a hover turned by 0.3 rad, the helix at 1.2 rad.
  EXPECT_TRUE(check_flight(artifact(), *make_hover({Eigen::Vector3d(0, 0, 2), 0.3}), 5.0).ok);
  EXPECT_TRUE(check_flight(artifact(), *make_helix({Eigen::Vector3d(0, 0, 4), 5.0, 3.0, M_PI / 40, 1.2}), 80.0).ok);
  // A turn: psi = w t on the spot, inside the 0.2 rad/s bound at 0.15, refused at 0.3
  // at its first sample past the bound.
  auto pirouette = [](double w) {
    std::string csv = "t,x,y,z,psi\n";
    for (int k = 0; k <= 100; ++k) {
      const double t = 0.1 * k;
      csv += std::to_string(t) + ",0,0,2," + std::to_string(std::remainder(w * t, 2 * M_PI)) + "\n";
    }
    return make_csv_trajectory(csv, "pirouette.csv");
  };
  EXPECT_TRUE(check_flight(artifact(), *pirouette(0.15), 9.0).ok) << check_flight(artifact(), *pirouette(0.15), 9.0).message;
  PreflightReport r = check_flight(artifact(), *pirouette(0.3), 9.0);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.message.find("t = 0 s: yaw rate 0.3"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("beyond the envelope's +- 0.2 rad/s"), std::string::npos) << r.message;
  // The acceleration box is the design's, in the reference's yaw frame: a straight
  // diagonal run at 0.07 m/s^2 is 0.049 per world axis, inside the +-0.06 box at yaw 0;
  // at yaw pi/4 all of it lies along the vehicle's x, outside.
  WaypointPath diagonal{{Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(6, 6, 2)}, 0.8, 0.07, 0.0};
  const auto straight = make_waypoints(diagonal);
  const double arrival = waypoint_schedule(diagonal).back();
  ASSERT_TRUE(std::isfinite(arrival));
  double peak = 0.0;
  for (double t = 0.0; t < arrival; t += 0.01) peak = std::max(peak, straight->at(t).a.head<2>().norm());
  EXPECT_NEAR(peak, 0.07, 0.005);
  r = check_flight(artifact(), *straight, arrival);
  EXPECT_TRUE(r.ok) << r.message;
  diagonal.yaw = M_PI / 4;
  r = check_flight(artifact(), *make_waypoints(diagonal), arrival);
  ASSERT_FALSE(r.ok);
  EXPECT_NE(r.message.find("acceleration x = 0.06"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("m/s^2 (in the reference's yaw frame) outside the envelope [-0.06, 0.06]"), std::string::npos)
      << r.message;
}

}  // namespace
}  // namespace tmpc
