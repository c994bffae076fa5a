// The tracking error x_tilde of thesis (5.5)-(5.7): differences to the reference, the
// yaw wrapped to (-pi, pi], the integrals of x, y, z, psi by the rectangle rule over
// the periods, for the tiltrotor's 20 + 4 states and for a smaller system.
#include <cmath>

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
}

}  // namespace
}  // namespace tmpc
