// The tracking error x_tilde of thesis (5.5)-(5.7): differences to the reference, the
// yaw wrapped to (-pi, pi], the integrals of x, y, z, psi by the rectangle rule over
// the periods, for the tiltrotor's 20 + 4 states and for a smaller system.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "tmpc/model/state_layout.hpp"
#include "tmpc/runtime/tracking_error.hpp"

namespace tmpc {
namespace {

constexpr int kPsi = 5;

/// The tiltrotor's error: 20 measured states, integrals of x, y, z, psi.
TrackingError tiltrotor_error() {
  std::vector<StateKind> kinds = tiltrotor_state_kinds();
  kinds.resize(20);
  return TrackingError(kinds, {0, 1, 2, kPsi});
}

Eigen::VectorXd reference(double psi) {
  Eigen::VectorXd r(20);
  r << 1.0, 2.0, 3.0, 0.01, 0.02, psi, 0.1, 0.2, 0.3, 0.4, 0.5, -0.5, 0.1, 0, 0, 0, 0, 0, 0, 0;
  return r;
}

TEST(TrackingError, DifferencesWithTheYawWrappedAcrossPi) {
  TrackingError e = tiltrotor_error();
  const Eigen::VectorXd r = reference(-3.1);
  Eigen::VectorXd x = r;
  x(0) += 0.25;   // x
  x(kPsi) = 3.1;  // 6.2 rad from the reference the long way, -0.083 the short way
  x(10) += -0.5;  // x velocity
  const Eigen::VectorXd& xt = e.update(x, r);
  ASSERT_EQ(xt.size(), 24);
  EXPECT_DOUBLE_EQ(xt(0), 0.25);
  EXPECT_NEAR(xt(kPsi), 6.2 - 2.0 * M_PI, 1e-12);
  EXPECT_DOUBLE_EQ(xt(10), -0.5);
  EXPECT_EQ(xt.tail<4>(), Eigen::Vector4d::Zero());  // no period integrated yet
  // A yaw error of exactly pi stays pi or -pi, never 3 pi.
  x(kPsi) = -3.1 + M_PI;
  EXPECT_NEAR(std::abs(e.update(x, r)(kPsi)), M_PI, 1e-12);
  // measured() is the same difference without the integrals.
  Eigen::VectorXd m = Eigen::VectorXd::Zero(20);
  e.measured(x, r, m);
  EXPECT_EQ(m, e.update(x, r).head(20));
}

TEST(TrackingError, IntegralsOfXYZPsiByTheRectangleRule) {
  TrackingError e = tiltrotor_error();
  const Eigen::VectorXd r = reference(0.0);
  Eigen::VectorXd x = r;
  const double dt = 0.012;
  double ix = 0.0, ipsi = 0.0;
  for (int k = 0; k < 100; ++k) {
    x(0) = r(0) + 0.01 * k;       // a growing x error
    x(kPsi) = 0.002;              // a constant yaw error
    x(3) = r(3) + 0.5;            // phi is not integrated
    const Eigen::VectorXd& xt = e.update(x, r);
    EXPECT_NEAR(xt(20), ix, 1e-12) << k;  // the integral up to the previous period
    EXPECT_NEAR(xt(23), ipsi, 1e-12) << k;
    e.integrate(dt);
    ix += dt * 0.01 * k;
    ipsi += dt * 0.002;
  }
  EXPECT_NEAR(e.update(x, r)(20), 0.01 * dt * 99 * 100 / 2, 1e-12);
  EXPECT_DOUBLE_EQ(e.value()(21), 0.0);  // y never had an error
  e.reset();
  EXPECT_EQ(e.value(), Eigen::VectorXd::Zero(24));
}

TEST(TrackingError, AnySizeAndNoWrapOutsideTheYaw) {
  // A mass-spring pair: two positions, two velocities, the first position integrated.
  TrackingError e({StateKind::Position, StateKind::Position, StateKind::Velocity, StateKind::Velocity}, {0});
  Eigen::VectorXd x(4), r = Eigen::VectorXd::Zero(4);
  x << 7.0, -7.0, 0.5, 0.0;  // 7 m is not wrapped: only a yaw is
  EXPECT_EQ(e.update(x, r).size(), 5);
  EXPECT_DOUBLE_EQ(e.value()(0), 7.0);
  EXPECT_DOUBLE_EQ(e.value()(1), -7.0);
  e.integrate(0.5);
  EXPECT_DOUBLE_EQ(e.update(x, r)(4), 3.5);
  EXPECT_EQ(e.measured_states(), 4);
  // No yaw: there is no yaw frame to take the errors in.
  EXPECT_THROW(e.set_yaw_frame(0.0), std::invalid_argument);
}

TEST(TrackingError, AnAnyYawDesignTakesTheHorizontalErrorsInTheReferencesYawFrame) {
  // The design's model at yaw 0.2; the reference a quarter turn from it: the world's
  // +x error lies on the vehicle's right (-y of its frame), +y ahead of it (+x).
  TrackingError e = tiltrotor_error(), world = tiltrotor_error();
  e.set_yaw_frame(0.2);
  const Eigen::VectorXd r = reference(0.2 + M_PI / 2);
  Eigen::VectorXd x = r;
  x(0) += 0.3;    // x
  x(1) += 0.1;    // y
  x(2) += -0.05;  // z: not turned
  x(3) += 0.02;   // phi: a tilt in the load's own frame, not turned
  x(kPsi) += 0.01;
  x(10) += 0.4;   // x velocity
  x(11) += -0.2;  // y velocity
  x(15) += 0.03;  // yaw rate
  const Eigen::VectorXd& xt = e.update(x, r);
  const Eigen::VectorXd& xw = world.update(x, r);
  EXPECT_NEAR(xt(0), 0.1, 1e-15);
  EXPECT_NEAR(xt(1), -0.3, 1e-15);
  EXPECT_NEAR(xt(10), -0.2, 1e-15);
  EXPECT_NEAR(xt(11), -0.4, 1e-15);
  for (int i : {2, 3, 4, kPsi, 6, 7, 8, 9, 12, 13, 14, 15, 16, 17, 18, 19}) EXPECT_EQ(xt(i), xw(i)) << i;
  // The integrals are of the turned errors.
  e.integrate(0.5);
  EXPECT_NEAR(e.update(x, r)(20), 0.05, 1e-15);
  EXPECT_NEAR(e.value()(21), -0.15, 1e-15);
  // At the design's yaw the frame is the world's, bit for bit.
  TrackingError at = tiltrotor_error();
  at.set_yaw_frame(0.2);
  const Eigen::VectorXd r0 = reference(0.2);
  Eigen::VectorXd x0 = r0;
  x0.head(3) += Eigen::Vector3d(0.3, 0.1, -0.05);
  x0.segment(10, 2) += Eigen::Vector2d(0.4, -0.2);
  EXPECT_EQ(at.update(x0, r0), tiltrotor_error().update(x0, r0));
}

}  // namespace
}  // namespace tmpc

namespace tmpc {
namespace {

ReferenceJoinSettings three_axis_join() {
  ReferenceJoinSettings s;
  s.position_rows = {0, 1, 2};
  s.velocity_rows = {10, 11, 12};
  s.speed_limit = Eigen::Vector3d(0.15, 0.25, 0.05);
  s.acceleration_limit = 0.03;
  s.dead_zone = Eigen::Vector3d::Constant(0.05);
  return s;
}

// The joined reference r + g0 (1 - s(t / T)): it starts at the vehicle (zero position
// error on the joined rows), its velocity shift is the derivative of its position
// shift (central differences), its peak speed and acceleration stay within the limits
// on every axis with one of them reached (T the shortest), and after T it is the
// mission's reference again. Offsets inside the dead zone are not joined.
TEST(ReferenceJoin, StartsAtTheVehicleAndReturnsWithinItsSpeedAndAccelerationLimits) {
  ReferenceJoin j(three_axis_join());
  Eigen::VectorXd e0 = Eigen::VectorXd::Zero(20);
  e0.head(3) << -0.6, 0.5, 0.03;  // z: inside the dead zone
  e0(10) = 0.01;
  j.start(e0);
  ASSERT_TRUE(j.active());
  EXPECT_EQ(j.offset(), Eigen::Vector3d(-0.6, 0.5, 0.0));
  // x: speed 1.875 * 0.6 / 0.15 = 7.5 s, acceleration sqrt(5.7735 * 0.6 / 0.03) = 10.75 s.
  EXPECT_NEAR(j.duration(), std::sqrt(5.7735 * 0.6 / 0.03), 1e-9);
  Eigen::VectorXd e = e0;
  j.apply(0.0, e);
  EXPECT_NEAR(e(0), 0.0, 1e-15);
  EXPECT_NEAR(e(1), 0.0, 1e-15);
  EXPECT_EQ(e(2), 0.03);  // not joined
  EXPECT_EQ(e(10), 0.01);  // at rest at the start
  const auto shift = [&](double t) {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(20);
    j.apply(t, z);
    return z;  // -(g0 (1 - s)) on positions, g0 s' / T on velocities
  };
  const double T = j.duration(), h = 1e-4;
  double v_peak[2] = {0, 0}, a_peak[2] = {0, 0};
  for (double t = h; t < T - h; t += T / 997.0) {
    const Eigen::VectorXd m = shift(t - h), c = shift(t), p = shift(t + h);
    for (int i = 0; i < 2; ++i) {
      // The velocity row's shift is the derivative of the position row's: e_j' = d e_j / dt.
      EXPECT_NEAR(c(10 + i), (p(i) - m(i)) / (2 * h), 1e-7) << "t " << t;
      v_peak[i] = std::max(v_peak[i], std::abs(c(10 + i)));
      a_peak[i] = std::max(a_peak[i], std::abs((p(10 + i) - m(10 + i)) / (2 * h)));
    }
  }
  EXPECT_LE(v_peak[0], 0.15 * (1 + 1e-6));
  EXPECT_LE(v_peak[1], 0.25 * (1 + 1e-6));
  EXPECT_LE(std::max(a_peak[0], a_peak[1]), 0.03 * (1 + 1e-4));
  EXPECT_GT(a_peak[0], 0.03 * 0.999);  // the binding limit is reached
  EXPECT_TRUE(shift(T).isZero(0.0));
  EXPECT_TRUE(shift(T + 5.0).isZero(0.0));
  // Every offset in the dead zone (a sensor's noise or bias at the start): no join.
  e0.head(3) << 0.04, -0.05, 0.0;
  j.start(e0);
  EXPECT_FALSE(j.active());
  EXPECT_TRUE(shift(1.0).isZero(0.0));
  EXPECT_THROW(ReferenceJoin(ReferenceJoinSettings{{0}, {}, Eigen::VectorXd(), 0.1, Eigen::VectorXd()}), std::invalid_argument);
}

// The tracking error with the join: the integrals integrate the joined error, and a
// reset() (a restart of the law) plans the join again from the next state.
TEST(ReferenceJoin, TheTrackingErrorIntegratesTheJoinedErrorAndRestartsIt) {
  TrackingError e = tiltrotor_error();
  e.set_join(three_axis_join());
  Eigen::VectorXd x = reference(0.0);
  x(0) += 0.4;
  const Eigen::VectorXd& xt = e.update(x, reference(0.0));
  EXPECT_NEAR(xt(0), 0.0, 1e-15);
  EXPECT_TRUE(e.join().active());
  double integral = 0.0;
  for (int k = 0; k < 100; ++k) {
    const double now = e.update(x, reference(0.0))(0);
    EXPECT_NEAR(e.value()(20), integral, 1e-12);
    integral += 0.012 * now;
    e.integrate(0.012);
  }
  EXPECT_GT(integral, 0.0);
  EXPECT_LT(integral, 0.4 * 1.2);  // far less than the unjoined 0.4 m for 1.2 s
  e.reset();
  x(0) = reference(0.0)(0) - 0.2;
  EXPECT_NEAR(e.update(x, reference(0.0))(0), 0.0, 1e-15);
  EXPECT_NEAR(e.join().offset()(0), -0.2, 1e-15);
  EXPECT_EQ(e.value()(20), 0.0);
}

}  // namespace
}  // namespace tmpc
