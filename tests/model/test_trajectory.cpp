// Reference trajectories: every shape's velocity and acceleration are the derivatives
// of its position (central finite differences are the oracle, not the formulas), the
// waypoint path passes its points at its schedule within its limits, the CSV path
// interpolates its rows, and bad CSV input names its line.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "tmpc/model/quintic_spline.hpp"
#include "tmpc/model/trajectory.hpp"

namespace tmpc {
namespace {

/// max over t of |v - dp/dt| and |a - dv/dt| by central differences, relative to the
/// size of the derivative (so fast and slow shapes are held to the same standard).
void expect_consistent_derivatives(const Trajectory& tr, double t0, double t1, double tol) {
  const double h = 1e-5;
  for (int k = 0; k <= 400; ++k) {
    const double t = t0 + (t1 - t0) * k / 400.0;
    const TrajectoryPoint p = tr.at(t), lo = tr.at(t - h), hi = tr.at(t + h);
    const Eigen::Vector3d v_fd = (hi.p - lo.p) / (2 * h), a_fd = (hi.v - lo.v) / (2 * h);
    EXPECT_LT((p.v - v_fd).norm(), tol * (1.0 + p.v.norm())) << tr.description() << " at t = " << t;
    EXPECT_LT((p.a - a_fd).norm(), tol * (1.0 + p.a.norm())) << tr.description() << " at t = " << t;
    EXPECT_NEAR(p.psi_d, (hi.psi - lo.psi) / (2 * h), tol * (1.0 + std::abs(p.psi_d)));
  }
}

TEST(Trajectory, HelixIsTheThesisHelix) {
  // Thesis 6.2: x = 5 cos(0.5 t), y = 5 sin(0.5 t), z = -6 - 2 cos(0.5 t) (z up here).
  const auto h = make_helix({Eigen::Vector3d(0, 0, 6), 5.0, 2.0, 0.5, 0.0});
  for (double t : {0.0, 1.3, 7.7, 40.0}) {
    const TrajectoryPoint p = h->at(t);
    EXPECT_NEAR(p.p.x(), 5 * std::cos(0.5 * t), 1e-12);
    EXPECT_NEAR(p.p.y(), 5 * std::sin(0.5 * t), 1e-12);
    EXPECT_NEAR(p.p.z(), 6 - 2 * std::cos(0.5 * t), 1e-12);
  }
  expect_consistent_derivatives(*h, 0.0, 20.0, 1e-6);
  EXPECT_TRUE(std::isinf(h->duration()));
}

TEST(Trajectory, ShapesHaveConsistentDerivatives) {
  expect_consistent_derivatives(*make_circle({Eigen::Vector3d(1, 2, 3), 2.0, 0.7, 0.3}), 0.0, 15.0, 1e-6);
  expect_consistent_derivatives(*make_figure_eight({Eigen::Vector3d(0, 0, 5), Eigen::Vector2d(4, 3), 0.4, 0.0}), 0.0,
                                20.0, 1e-6);
  const auto hover = make_hover({Eigen::Vector3d(1, -1, 4), 0.2});
  const TrajectoryPoint p = hover->at(12.0);
  EXPECT_EQ(p.p, Eigen::Vector3d(1, -1, 4));
  EXPECT_EQ(p.v.norm() + p.a.norm(), 0.0);
  EXPECT_DOUBLE_EQ(p.psi, 0.2);
}

TEST(Trajectory, FigureEightCrossesItsCenterTwicePerPeriod) {
  const double w = 0.4;
  const auto e = make_figure_eight({Eigen::Vector3d(0, 0, 5), Eigen::Vector2d(4, 3), w, 0.0});
  EXPECT_LT((e->at(0.0).p - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
  EXPECT_LT((e->at(M_PI / w).p - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
  EXPECT_NEAR(e->at(0.5 * M_PI / w).p.x(), 4.0, 1e-12);  // the lobes reach +-ax
  EXPECT_NEAR(e->at(1.5 * M_PI / w).p.x(), -4.0, 1e-12);
}

TEST(Trajectory, WaypointsPassTheirPointsWithinTheLimits) {
  WaypointPath w;
  w.points = {Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(4, 0, 6), Eigen::Vector3d(4, 3, 6), Eigen::Vector3d(0, 3, 5)};
  w.max_speed = 1.2;
  w.max_acceleration = 0.35;
  const auto tr = make_waypoints(w);
  const std::vector<double> t = waypoint_schedule(w);
  ASSERT_EQ(t.size(), w.points.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_LT((tr->at(t[k]).p - w.points[k]).norm(), 1e-9) << "waypoint " << k;
  }
  // At rest at both ends, and it holds the last point for ever.
  EXPECT_LT(tr->at(0.0).v.norm() + tr->at(0.0).a.norm(), 1e-9);
  EXPECT_LT(tr->at(t.back()).v.norm() + tr->at(t.back()).a.norm(), 1e-9);
  EXPECT_LT((tr->at(t.back() + 100.0).p - w.points.back()).norm(), 1e-12);
  EXPECT_TRUE(std::isinf(tr->duration()));
  // Limits, sampled more densely than the schedule sampled them (1 % slack for that),
  // and the schedule is tight: one of the two limits is nearly reached.
  double v_peak = 0, a_peak = 0;
  for (int k = 0; k <= 20000; ++k) {
    const TrajectoryPoint p = tr->at(t.back() * k / 20000.0);
    v_peak = std::max(v_peak, p.v.norm());
    a_peak = std::max(a_peak, p.a.norm());
  }
  EXPECT_LE(v_peak, w.max_speed * 1.01);
  EXPECT_LE(a_peak, w.max_acceleration * 1.01);
  EXPECT_GT(std::max(v_peak / w.max_speed, a_peak / w.max_acceleration), 0.95);
  expect_consistent_derivatives(*tr, 0.0, t.back(), 1e-5);
}

TEST(Trajectory, WaypointsRefuseDegeneratePaths) {
  WaypointPath w;
  w.max_speed = 1.0;
  w.max_acceleration = 1.0;
  w.points = {Eigen::Vector3d(0, 0, 5)};
  EXPECT_THROW(make_waypoints(w), std::invalid_argument);
  w.points = {Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(0, 0, 5)};
  try {
    make_waypoints(w);
    FAIL() << "a repeated point was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 repeats point 0"), std::string::npos) << e.what();
  }
  w.points = {Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(1, 0, 5)};
  w.max_speed = 0.0;
  EXPECT_THROW(make_waypoints(w), std::invalid_argument);
}

TEST(QuinticSpline, IsC4AtItsKnots) {
  // Third derivative continuous across knots (C4 implies it), by one-sided limits.
  const QuinticSpline s({0.0, 1.0, 2.5, 3.0, 5.0}, {0.0, 2.0, -1.0, 0.5, 3.0}, QuinticSpline::Ends::Natural);
  for (double knot : {1.0, 2.5, 3.0}) {
    double y0, d0, dd0, ddd0, y1, d1, dd1, ddd1;
    s.evaluate(knot - 1e-9, y0, d0, dd0, ddd0);
    s.evaluate(knot + 1e-9, y1, d1, dd1, ddd1);
    EXPECT_NEAR(y0, y1, 1e-7);
    EXPECT_NEAR(d0, d1, 1e-6);
    EXPECT_NEAR(dd0, dd1, 1e-6);
    EXPECT_NEAR(ddd0, ddd1, 1e-5);
  }
  EXPECT_NEAR(s.value(2.5), -1.0, 1e-12);
  EXPECT_THROW(QuinticSpline({0.0, 0.0}, {1.0, 2.0}, QuinticSpline::Ends::Natural), std::invalid_argument);
}

TEST(Trajectory, CsvInterpolatesItsRows) {
  std::string csv = "# a slow circle\nt, x, y, z, psi\n";
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.5 * k;
    csv += std::to_string(t) + "," + std::to_string(2 * std::cos(0.2 * t)) + "," + std::to_string(2 * std::sin(0.2 * t)) +
           ",5," + std::to_string(std::remainder(0.3 * t, 2 * M_PI)) + "\n";
  }
  const auto tr = make_csv_trajectory(csv, "circle.csv");
  EXPECT_NEAR(tr->duration(), 20.0, 1e-9);
  // Between rows the spline is close to the circle it samples (the rows are 6 digits).
  const TrajectoryPoint p = tr->at(7.25);
  EXPECT_NEAR(p.p.x(), 2 * std::cos(0.2 * 7.25), 1e-4);
  EXPECT_NEAR(p.v.y(), 0.4 * std::cos(0.2 * 7.25), 1e-3);
  EXPECT_NEAR(p.psi, 0.3 * 7.25, 1e-4);  // unwrapped, not sawtoothed
  EXPECT_NEAR(p.psi_d, 0.3, 1e-3);
  expect_consistent_derivatives(*tr, 0.1, 19.9, 1e-5);
}

std::string csv_error(const std::string& text) {
  try {
    make_csv_trajectory(text, "track.csv");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Trajectory, CsvErrorsNameTheLine) {
  const std::string head = "t,x,y,z,psi\n0,0,0,5,0\n1,1,0,5,0\n";
  EXPECT_NE(csv_error("time,x,y,z\n0,0,0,5,0\n").find("track.csv: line 1: expected the header"), std::string::npos);
  EXPECT_NE(csv_error(head + "2,1,0,five,0\n3,1,0,5,0\n").find("line 4: 'five' in column 4 is not a number"),
            std::string::npos);
  EXPECT_NE(csv_error(head + "1,1,0,5,0\n3,1,0,5,0\n").find("line 4: time 1 is not after 1"), std::string::npos);
  EXPECT_NE(csv_error(head + "2,1,0,5\n").find("line 4: expected 5 columns"), std::string::npos);
  EXPECT_NE(csv_error(head + "2,1,0,nan,0\n3,1,0,5,0\n").find("line 4: column 4 is not finite"), std::string::npos);
  EXPECT_NE(csv_error(head).find("2 rows of data"), std::string::npos);
  EXPECT_NE(csv_error("t,x,y,z,psi\n1,0,0,5,0\n2,0,0,5,0\n3,0,0,5,0\n4,0,0,5,0\n").find("starts at t = 0"),
            std::string::npos);
  EXPECT_THROW(load_csv_trajectory("/nonexistent/track.csv"), std::invalid_argument);
  EXPECT_THROW(load_csv_trajectory("/dev/null"), std::invalid_argument);  // not a regular file
}

}  // namespace
}  // namespace tmpc
