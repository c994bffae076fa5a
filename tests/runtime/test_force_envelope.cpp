// The force envelope: the rod's static tilt under a scenario's forces on the load, and
// the windows certified outside the box for every controller (force_envelope.hpp).
// Oracles: the rod's slope bounds worked out by hand from the box (below); the
// simulator's settled attitude under a force is in tests/metrics/test_scenarios.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/runtime/force_envelope.hpp"

namespace tmpc {
namespace {

const ControllerArtifact& artifact() {
  static const ControllerArtifact a = test::quick_artifact();
  return a;
}

/// Hovering 10 s with a constant force on the load from t = 0.
ForceEnvelopeReport hover_with(const Eigen::Vector3d& f, double duration = 10.0) {
  std::ostringstream y;
  y << "name: hover_force\nduration: " << duration
    << "\ntrajectory: {type: hover, position: [0.0, 0.0, 3.0], yaw: 0.0}\n"
       "disturbances:\n  - {type: step, time: 0.0, force: ["
    << f.x() << ", " << f.y() << ", " << f.z() << "]}\n";
  const Scenario s = scenario_from_string(y.str(), "hover_force.yaml");
  return check_force_envelope(artifact(), *s.trajectory, s.disturbances, s.duration);
}

TEST(ForceEnvelope, TheBoxIsWhatTheCertificatesAssume) {
  // The slope bounds below are worked out for this box: phi, theta, psi within 0.5 rad,
  // the load's speeds within 0.6, 1.0, 0.2 m/s, a 0.5 kg load.
  for (const char* s : {"phi", "theta", "psi"}) {
    const auto i = std::find(artifact().state_names.begin(), artifact().state_names.end(), s) - artifact().state_names.begin();
    EXPECT_NEAR(artifact().X.hi(i) / artifact().N_x(i), 0.5, 1e-12) << s;
  }
  EXPECT_DOUBLE_EQ(artifact().vehicle.load_mass, 0.5);
}

TEST(ForceEnvelope, AForceTheBoxHoldsIsNotCertified) {
  // phi = atan(F_y / (m_L g)) = 0.42 rad: 0.84 of the bound, at hover's zero reference.
  const double mg = 0.5 * artifact().vehicle.gravity;
  const ForceEnvelopeReport r = hover_with(Eigen::Vector3d(0.0, mg * std::tan(0.42), 0.0));
  ASSERT_TRUE(r.applicable) << r.message;
  EXPECT_NEAR(r.static_peak, 0.84, 1e-3);
  EXPECT_EQ(r.static_peak_state, "phi");
  EXPECT_DOUBLE_EQ(r.static_outside, 0.0);
  EXPECT_TRUE(r.certified.empty());
  EXPECT_TRUE(r.certified_reference_yaw.empty());
}

TEST(ForceEnvelope, PastTheHeldYawsSlopesButInsideTheYawedOnes) {
  // Yaw held at 0: the rod's lateral slope r_y / r_z = -tan(phi) / cos(theta) reaches at
  // most tan(0.5) / cos(0.5) = 0.6225 in y (a mean of theta = +-0.5 swings; the box's
  // edge at theta = 0 is tan(0.5) = 0.546), and over a window of T s the load's speed
  // box (1 m/s in y) allows a mean m_L a_y of 1 / T N, 0.204 / T of m_L g. A slope of
  // 0.75 is past 0.6225 + 0.102 for T = 2 s, not for 1 s: 2 s windows are certified. Yawed by 0.5 rad the box's corner (phi = theta = 0.5) has the
  // slope length sqrt(tan^2 0.5 + tan^2 0.5 / cos^2 0.5) = 0.828 and lies, rotated, at
  // atan(...) from the y axis within reach: nothing certified for every controller.
  const double mg = 0.5 * artifact().vehicle.gravity;
  const ForceEnvelopeReport r = hover_with(Eigen::Vector3d(0.0, 0.75 * mg, 0.0));
  ASSERT_TRUE(r.applicable) << r.message;
  EXPECT_NEAR(r.static_peak, std::atan(0.75) / 0.5, 1e-3);
  EXPECT_GT(r.static_outside, 9.9);
  EXPECT_TRUE(r.certified.empty()) << r.message;
  ASSERT_FALSE(r.certified_reference_yaw.empty()) << r.message;
  // Disjoint 2 s windows from every 10th period: [0, 2], [2.04, 4.04], ... 4 in 10 s.
  EXPECT_EQ(r.certified_reference_yaw.size(), 4u);
  EXPECT_NEAR(r.certified_reference_yaw[0].end - r.certified_reference_yaw[0].start, 2.0, artifact().sample_time);
  for (std::size_t k = 1; k < r.certified_reference_yaw.size(); ++k)
    EXPECT_GT(r.certified_reference_yaw[k].start, r.certified_reference_yaw[k - 1].end);
  // Inside the held yaw's reach with the 8 s windows' margin (0.58 < 0.6225 + 0.0255):
  // no certificate.
  EXPECT_TRUE(hover_with(Eigen::Vector3d(0.0, 0.58 * mg, 0.0)).certified_reference_yaw.empty());
}

TEST(ForceEnvelope, PastEveryYawTheBoxAllowsIsCertifiedForEveryController) {
  // A slope of 1.2 (phi 0.876 rad) is past the 0.828 any yaw reaches.
  const double mg = 0.5 * artifact().vehicle.gravity;
  for (const Eigen::Vector3d& f : {Eigen::Vector3d(0.0, 1.2 * mg, 0.0), Eigen::Vector3d(-1.2 * mg, 0.0, 0.0),
                                   Eigen::Vector3d(0.85 * mg, 0.85 * mg, 0.0)}) {
    const ForceEnvelopeReport r = hover_with(f);
    EXPECT_FALSE(r.certified.empty()) << f.transpose() << ": " << r.message;
    EXPECT_NE(r.message.find("no controller flies this without violations"), std::string::npos) << r.message;
  }
  // An upward force lightens the load and tilts the rod further: 0.5 m_L g sideways
  // with 0.6 m_L g upwards is a slope of 1.25.
  EXPECT_FALSE(hover_with(Eigen::Vector3d(0.0, 0.5 * mg, 0.6 * mg)).certified.empty());
  EXPECT_TRUE(hover_with(Eigen::Vector3d(0.0, 0.5 * mg, 0.0)).certified.empty());
}

TEST(ForceEnvelope, OnlyForALoadOnARod) {
  const Scenario s = test::shipped_scenario("mass_spring_steps");
  const ForceEnvelopeReport r = check_force_envelope(test::mass_spring_artifact(), *s.trajectory, s.disturbances, s.duration);
  EXPECT_FALSE(r.applicable);
  EXPECT_EQ(r.message, "no load on a rod in this model");
  const Scenario quiet = test::quiet_helix();
  const ForceEnvelopeReport q = check_force_envelope(artifact(), *quiet.trajectory, quiet.disturbances, 10.0);
  EXPECT_FALSE(q.applicable);
  EXPECT_EQ(q.message, "no force on the load");
}

TEST(ForceEnvelope, TheBestYawSplitsTheTiltBetweenPhiAndTheta) {
  // A force F_y = c m_L g at hover: the rod along (0, -c, 1). Turned by the yaw d the
  // vehicle sees it at phi = asin(c cos d / sqrt(1 + c^2)), theta = atan(c sin d): phi
  // falls and theta grows with |d|. For c = 0.75 and 0.6 phi stays the larger up to the
  // yaw's bound (0.5), so the best yaw is the bound: ratios asin(0.6 cos 0.5) / 0.5 =
  // 1.109 (outside the whole flight) and asin(0.6 / sqrt(1.36) cos 0.5) / 0.5 = 0.937
  // (inside, where the reference yaw has atan(0.6) / 0.5 = 1.08).
  const double mg = 0.5 * artifact().vehicle.gravity;
  for (const double c : {0.75, 0.6}) {
    const ForceEnvelopeReport r = hover_with(Eigen::Vector3d(0.0, c * mg, 0.0));
    ASSERT_TRUE(r.applicable) << r.message;
    const double d = 0.5;
    const double phi = std::asin(c * std::cos(d) / std::sqrt(1.0 + c * c)), theta = std::atan(c * std::sin(d));
    ASSERT_GT(phi, theta);
    const double exact = phi / 0.5;
    std::printf("F_y = %.2f m_L g: reference yaw %.4f, best yaw %.4f (exact %.4f), outside %.2f s\n", c, r.static_peak,
                r.static_peak_best_yaw, exact, r.static_outside_best_yaw);
    EXPECT_NEAR(r.static_peak, std::atan(c) / 0.5, 1e-3);
    EXPECT_GE(r.static_peak_best_yaw, exact - 1e-9);  // a grid's minimum: never below the exact one
    EXPECT_LE(r.static_peak_best_yaw, exact + 1e-3);
    EXPECT_NEAR(r.static_outside_best_yaw, exact > 1.0 ? 10.0 : 0.0, 0.02);
    // The yaws that bring it inside: phi <= 0.5 where cos d <= sin 0.5 sqrt(1 + c^2) / c
    // (theta = atan(c sin d) stays inside up to the bound), i.e. |d| in [d0, 0.5]: two
    // arcs of 0.5 - d0 each, from -0.5 to 0.5 with the gap around the reference; none
    // for 0.75 (outside at every yaw).
    if (exact > 1.0) {
      EXPECT_EQ(r.yaw_window_min, 0.0);
    } else {
      const double d0 = std::acos(std::sin(0.5) * std::sqrt(1.0 + c * c) / c);
      EXPECT_NEAR(r.yaw_window_min, 2.0 * (0.5 - d0), 2e-3);
      EXPECT_NEAR(r.yaw_window_first, -0.5, 1e-9);
      EXPECT_NEAR(r.yaw_window_last, 0.5, 1e-9);
    }
  }
  EXPECT_NEAR(std::acos(std::sin(0.5) * std::sqrt(1.36) / 0.6), 0.3714, 1e-4);  // d0 for c = 0.6
  EXPECT_NEAR(std::asin(0.6 * std::cos(0.5)) / 0.5, 1.109, 1e-3);  // the figures above
  EXPECT_NEAR(std::asin(0.6 / std::sqrt(1.36) * std::cos(0.5)) / 0.5, 0.937, 1e-3);
}

TEST(ForceEnvelope, TheShippedScenarios) {
  // README ("Noisy sensors, gusts and soft constraints"): the thesis' steps stay inside;
  // the gusts of seed 3 push the static tilt past the phi bound at the reference yaw
  // but certify nothing (a controller might yaw or swing the load); 3 N sustained and
  // 2 N gusts are certified for a controller that holds the yaw; 4 N for every one.
  // At the best yaw (the vehicle turned within psi's bound) the gusts and 3 N stay
  // inside the box statically; 2 N gusts and 4 N do not.
  struct Expect {
    const char* name;
    double peak, outside;
    std::size_t every, held;
    double best_yaw, best_yaw_outside;
  };
  for (const Expect& e : {Expect{"thesis_helix", 0.501, 0.0, 0, 0, 0.497, 0.0}, Expect{"gusts", 1.183, 6.74, 0, 0, 0.939, 0.0},
                          Expect{"gusts_2n", 1.389, 13.9, 0, 6, 1.087, 10.6},
                          Expect{"sustained_force", 1.104, 70.0, 0, 17, 0.992, 0.0},
                          Expect{"sustained_force_4n", 1.375, 70.0, 8, 64, 1.249, 70.0}}) {
    const Scenario s = test::shipped_scenario(e.name);
    const ForceEnvelopeReport r = check_force_envelope(artifact(), *s.trajectory, s.disturbances, s.duration);
    ASSERT_TRUE(r.applicable) << e.name;
    std::printf("%s: best yaw %.4f (t = %.2f s), outside %.2f s\n", e.name, r.static_peak_best_yaw,
                r.static_peak_best_yaw_time, r.static_outside_best_yaw);
    EXPECT_NEAR(r.static_peak, e.peak, 2e-3) << e.name;
    EXPECT_NEAR(r.static_outside, e.outside, 0.1) << e.name;
    EXPECT_NEAR(r.static_peak_best_yaw, e.best_yaw, 2e-3) << e.name;
    EXPECT_NEAR(r.static_outside_best_yaw, e.best_yaw_outside, 0.1) << e.name;
    EXPECT_LE(r.static_peak_best_yaw, r.static_peak) << e.name;
    EXPECT_EQ(r.certified.size(), e.every) << e.name << ": " << r.message;
    EXPECT_EQ(r.certified_reference_yaw.size(), e.held) << e.name << ": " << r.message;
  }
}

TEST(ForceEnvelope, HalfTheGustSeedsPushTheStaticTiltOutOfTheBox) {
  // README: the gusts scenario with seeds 1 to 11 (the shipped one is 3): in six the
  // 1.5 N gust lines up with the steps and the static tilt at the reference yaw leaves
  // the box for seconds; none is certified for every controller, and at the best yaw
  // none leaves the box.
  Scenario s = test::shipped_scenario("gusts");
  std::vector<unsigned> outside;
  for (unsigned seed = 1; seed <= 11; ++seed) {
    std::vector<DisturbanceEvent> events = s.disturbances.events();
    for (DisturbanceEvent& e : events)
      if (e.kind == DisturbanceEvent::Kind::Gust) e.seed = seed;
    const ForceEnvelopeReport r = check_force_envelope(artifact(), *s.trajectory, DisturbanceProfile(events), s.duration);
    std::printf("gust seed %u: static peak %.3f, outside %.2f s, best yaw %.4f, outside %.2f s, certified %zu (held yaw %zu)\n",
                seed, r.static_peak, r.static_outside, r.static_peak_best_yaw, r.static_outside_best_yaw,
                r.certified.size(), r.certified_reference_yaw.size());
    if (r.static_outside > 1.0) {
      outside.push_back(seed);
      EXPECT_GE(r.static_outside, 4.0) << seed;  // README: "for 4 to 7 s"
      EXPECT_LE(r.static_outside, 7.0) << seed;
    }
    EXPECT_TRUE(r.certified.empty()) << seed;
    // README: how precisely the yaw must be held where the reference yaw's tilt is
    // outside: 0.13 to 0.32 rad of yaws in five seeds, 0.02 rad (1.2 degrees, -0.209 to
    // -0.189 rad off the reference, at 62.96 s) in seed 6.
    if (r.static_outside > 0.0) {
      std::printf("  the narrowest yaw window %.4f rad at %.2f s (%.3f to %.3f)\n", r.yaw_window_min, r.yaw_window_time,
                  r.yaw_window_first, r.yaw_window_last);
      if (seed == 6) {
        EXPECT_NEAR(r.yaw_window_min, 0.0205, 1.5e-3);
        EXPECT_NEAR(r.yaw_window_first, -0.209, 2e-3);
        EXPECT_NEAR(r.yaw_window_last, -0.189, 2e-3);
        EXPECT_NEAR(r.yaw_window_time, 62.96, 0.05);
      } else {
        EXPECT_GT(r.yaw_window_min, 0.13) << seed;
        EXPECT_LT(r.yaw_window_min, 0.325) << seed;
      }
    } else {
      EXPECT_TRUE(std::isinf(r.yaw_window_min)) << seed;
    }
    // README: at the best yaw every seed's static tilt stays inside (at most 0.99).
    EXPECT_LT(r.static_peak_best_yaw, 0.995) << seed;
    EXPECT_DOUBLE_EQ(r.static_outside_best_yaw, 0.0) << seed;
    if (r.static_outside <= 1.0) {
      EXPECT_DOUBLE_EQ(r.static_outside, 0.0) << seed;
    }
  }
  EXPECT_EQ(outside, (std::vector<unsigned>{1, 2, 3, 6, 8, 11}));
}

}  // namespace
}  // namespace tmpc
