// Disturbance profiles: the thesis' cumulative steps, ramps and sines by their
// definitions, and the gust against its filter ODE (tau F' + F = command, checked by
// finite differences), its continuity, bounds, seeding and decay.
#include <gtest/gtest.h>

#include <cmath>

#include "tmpc/sim/disturbance.hpp"

namespace tmpc {
namespace {

DisturbanceEvent step(double t, Eigen::Vector3d f, DisturbanceEvent::Target on = DisturbanceEvent::Target::Load) {
  DisturbanceEvent e;
  e.start = t;
  e.force = f;
  e.target = on;
  return e;
}

DisturbanceEvent gust(std::uint32_t seed, double start = 0.0, double end = 1e9) {
  DisturbanceEvent e;
  e.kind = DisturbanceEvent::Kind::Gust;
  e.start = start;
  e.end = end;
  e.magnitude = 1.5;
  e.time_constant = 0.8;
  e.redraw = 3.0;
  e.seed = seed;
  return e;
}

TEST(DisturbanceProfile, ThesisStepsAreCumulative) {
  const DisturbanceProfile s = DisturbanceProfile::steps(
      {{20.0, Eigen::Vector3d(1, 0, 0)}, {40.0, Eigen::Vector3d(0, 1, 0)}, {60.0, Eigen::Vector3d(0, 0, 1)}});
  EXPECT_EQ(s.load_force(19.999), Eigen::Vector3d::Zero());
  EXPECT_EQ(s.load_force(20.0), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.load_force(39.9), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.load_force(40.0), Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(s.load_force(80.0), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(s.body_force(80.0), Eigen::Vector3d::Zero());
  EXPECT_EQ(s.event_times(), (std::vector<double>{20.0, 40.0, 60.0}));
}

TEST(DisturbanceProfile, EmptyMeansNoForceAndTargetsAreSeparate) {
  EXPECT_EQ(DisturbanceProfile{}.load_force(100.0), Eigen::Vector3d::Zero());
  const DisturbanceProfile s({step(5.0, Eigen::Vector3d(0, 0, 2), DisturbanceEvent::Target::Body),
                              step(1.0, Eigen::Vector3d(1, 0, 0)), step(5.0, Eigen::Vector3d(0, 1, 0))});
  EXPECT_EQ(s.load_force(2.0), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.load_force(6.0), Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(s.body_force(6.0), Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(s.event_times(), (std::vector<double>{1.0, 5.0}));  // sorted, unique
}

TEST(DisturbanceProfile, RampsAndSinesFollowTheirDefinitions) {
  DisturbanceEvent r;
  r.kind = DisturbanceEvent::Kind::Ramp;
  r.start = 10.0;
  r.end = 20.0;
  r.force = Eigen::Vector3d(0, 0.5, 0);
  DisturbanceEvent s;
  s.kind = DisturbanceEvent::Kind::Sine;
  s.start = 2.0;
  s.end = 30.0;
  s.force = Eigen::Vector3d(0.3, 0, 0);
  s.frequency = 0.5;
  s.phase = 0.25;
  const DisturbanceProfile p({r, s});
  EXPECT_NEAR(p.load_force(15.0).y(), 0.25, 1e-15);
  EXPECT_NEAR(p.load_force(25.0).y(), 0.5, 1e-15);  // held after the end
  EXPECT_EQ(p.load_force(9.0).y(), 0.0);
  EXPECT_NEAR(p.load_force(3.3).x(), 0.3 * std::sin(2 * M_PI * 0.5 * 1.3 + 0.25), 1e-15);
  EXPECT_EQ(p.load_force(31.0).x(), 0.0);  // the sine stops at its end
}

TEST(DisturbanceProfile, GustSolvesItsFilterEquation) {
  const DisturbanceEvent e = gust(3);
  const DisturbanceProfile p({e});
  const double h = 1e-5;
  double peak = 0.0;
  for (int k = 1; k < 2000; ++k) {
    const double t = 0.0317 * k;
    if (std::abs(std::remainder(t, e.redraw)) < 10 * h) continue;  // not across a redraw
    const Eigen::Vector3d f = p.load_force(t);
    const Eigen::Vector3d df = (p.load_force(t + h) - p.load_force(t - h)) / (2 * h);
    // tau F' + F is the command: constant within a redraw interval, of norm `magnitude`.
    const Eigen::Vector3d c = e.time_constant * df + f;
    EXPECT_NEAR(c.norm(), e.magnitude, 1e-5) << "t = " << t;
    peak = std::max(peak, f.norm());
  }
  EXPECT_LE(peak, e.magnitude + 1e-12);  // a first-order lag never overshoots its command
  EXPECT_GT(peak, 0.5 * e.magnitude);
  // Continuous across redraws, zero at its start.
  for (int i = 1; i < 10; ++i) {
    EXPECT_LT((p.load_force(i * e.redraw + 1e-9) - p.load_force(i * e.redraw - 1e-9)).norm(), 1e-6);
  }
  EXPECT_LT(p.load_force(0.0).norm(), 1e-12);
}

TEST(DisturbanceProfile, GustIsSeededHorizontalWhenAskedAndDiesOut) {
  const DisturbanceProfile a({gust(3)}), b({gust(3)}), c({gust(4)});
  EXPECT_EQ(a.load_force(17.3), b.load_force(17.3));
  EXPECT_GT((a.load_force(17.3) - c.load_force(17.3)).norm(), 1e-3);
  DisturbanceEvent flat = gust(5, 2.0, 20.0);
  flat.horizontal = true;
  flat.target = DisturbanceEvent::Target::Body;
  const DisturbanceProfile p({flat});
  EXPECT_EQ(p.body_force(11.0).z(), 0.0);
  EXPECT_GT(p.body_force(11.0).norm(), 0.0);
  EXPECT_EQ(p.load_force(11.0), Eigen::Vector3d::Zero());
  EXPECT_EQ(p.body_force(1.9), Eigen::Vector3d::Zero());
  // After its end it decays with the filter's time constant.
  const Eigen::Vector3d at_end = p.body_force(20.0);
  EXPECT_NEAR(p.body_force(20.0 + flat.time_constant).norm(), at_end.norm() * std::exp(-1.0), 1e-9);
}

TEST(DisturbanceProfile, BadEventsAreNamed) {
  DisturbanceEvent e = step(5.0, Eigen::Vector3d(1, 0, 0));
  e.end = 4.0;
  try {
    DisturbanceProfile({step(1.0, Eigen::Vector3d::Zero()), e});
    FAIL() << "an event ending before its start was accepted";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("disturbance 1"), std::string::npos) << err.what();
  }
  DisturbanceEvent g = gust(1);
  g.time_constant = 0.0;
  EXPECT_THROW(DisturbanceProfile({g}), std::invalid_argument);
  DisturbanceEvent r;
  r.kind = DisturbanceEvent::Kind::Ramp;
  EXPECT_THROW(DisturbanceProfile({r}), std::invalid_argument);  // a ramp needs an end
}

}  // namespace
}  // namespace tmpc
