// Hover equilibrium and feedforward: the thesis equilibrium (section 6.2) is
// reproduced, and u_r of (5.4) is the equilibrium input at hover.
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/reference.hpp"

namespace tmpc {
namespace {

TEST(Equilibrium, ReproducesTheThesisEquilibrium) {
  const TiltrotorModel model(test::default_config().vehicle);
  const Equilibrium eq = solve_hover_equilibrium(model);
  // Thesis 6.2: gamma_1 = 1.3170e-4, gamma_2 = 0.01396, alpha_r = 0.0140, alpha_l = 0.0138;
  // hover thrusts from the vehicle code behind the thesis: 11.732257, 11.767602 N.
  EXPECT_NEAR(eq.angles(0) / 1.3170e-4, 1.0, 1e-3);
  EXPECT_NEAR(eq.angles(1) / 0.01396, 1.0, 1e-3);
  EXPECT_NEAR(eq.angles(2) / 0.0140053, 1.0, 1e-3);
  EXPECT_NEAR(eq.angles(3) / 0.0138091, 1.0, 1e-3);
  EXPECT_NEAR(eq.u(0), 11.732257, 1e-3);
  EXPECT_NEAR(eq.u(1), 11.767602, 1e-3);
  EXPECT_LT(std::abs(eq.u(2)), 1e-5);
  EXPECT_LT(std::abs(eq.u(3)), 2e-5);
  EXPECT_LT(eq.residual, 1e-10);
  // The equilibrium is a rest point of f (independent check through the full model).
  const Vec10 qdd = model.acceleration(eq.q(), Vec10::Zero(), eq.u, Eigen::Vector3d::Zero());
  EXPECT_LT(qdd.cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Equilibrium, ExistsAtAnyYaw) {
  const TiltrotorModel model(test::default_config().vehicle);
  const Equilibrium e0 = solve_hover_equilibrium(model, 0.0);
  const Equilibrium e1 = solve_hover_equilibrium(model, 1.0);
  // Yaw symmetry: gravity is along z, so the equilibrium does not depend on psi.
  EXPECT_LT((e0.angles - e1.angles).norm(), 1e-9);
  EXPECT_LT((e0.u - e1.u).norm(), 1e-8);
}

TEST(Feedforward, AtHoverIsTheEquilibriumInput) {
  const Config& cfg = test::default_config();
  const TiltrotorModel model(cfg.vehicle);
  const Equilibrium eq = solve_hover_equilibrium(model);
  ReferencePoint r;
  r.q = eq.q();
  EXPECT_LT((feedforward(model, r) - eq.u).norm(), 1e-9);
}

TEST(Feedforward, HelixStartsOnTheReferenceWithTheThesisNumbers) {
  const Config& cfg = test::default_config();
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator traj(model, test::thesis_helix());
  const ReferencePoint r0 = traj.at(0.0);
  EXPECT_NEAR(r0.q(kX), 5.0, 1e-12);
  EXPECT_NEAR(r0.q(kY), 0.0, 1e-12);
  EXPECT_NEAR(r0.q(kZ), 1.0, 1e-12);  // E8: z_r(0) = 4 - 3 = 1 m
  // Derivatives of the load position against central differences.
  const double t = 13.7, h = 1e-5;
  const ReferencePoint r = traj.at(t);
  const Vec10 v = (traj.at(t + h).q - traj.at(t - h).q) / (2 * h);
  const Vec10 a = (traj.at(t + h).qd - traj.at(t - h).qd) / (2 * h);
  EXPECT_LT((r.qd.head<3>() - v.head<3>()).norm(), 1e-8);
  EXPECT_LT((r.qdd.head<3>() - a.head<3>()).norm(), 1e-8);
  // The trimmed attitude varies slowly: its neglected rate is tiny.
  EXPECT_LT(v.tail<7>().cwiseAbs().maxCoeff(), 1e-3);
}

TEST(Trim, AtZeroAccelerationIsTheHoverEquilibrium) {
  const TiltrotorModel model(test::default_config().vehicle);
  const Equilibrium eq = solve_hover_equilibrium(model);
  const Trim t = solve_trim(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, eq);
  EXPECT_LT(t.attitude.norm(), 1e-9);
  EXPECT_LT((t.angles - eq.angles).norm(), 1e-9);
  EXPECT_LT((t.u - eq.u).norm(), 1e-8);
}

TEST(Trim, RealizesTheAccelerationThroughTheFullModel) {
  // Independent check: the plant's q'' at the trim state equals (sigma, 0).
  const TiltrotorModel model(test::default_config().vehicle);
  const Equilibrium eq = solve_hover_equilibrium(model);
  const Eigen::Vector3d sigma(-0.03, 0.02, 0.018), v(0.1, 0.39, -0.2);
  const Trim t = solve_trim(model, sigma, v, 0.3, eq);
  Vec10 q = Vec10::Zero(), qd = Vec10::Zero();
  q.segment<2>(kPhi) = t.attitude;
  q(kPsi) = 0.3;
  q.segment<4>(kGamma1) = t.angles;
  qd.head<3>() = v;
  Vec10 expected = Vec10::Zero();
  expected.head<3>() = sigma;
  EXPECT_LT((model.acceleration(q, qd, t.u, Eigen::Vector3d::Zero()) - expected).cwiseAbs().maxCoeff(), 1e-9);
  // A suspended load in steady acceleration hangs along the specific force: the load
  // frame's z axis, R_IL e_z with R_IL = Rz(psi) Ry(theta) Rx(phi), is parallel to
  // sigma + g e_z (a pendulum's relative equilibrium; friction on x, y, z is zero).
  const double phi = t.attitude(0), theta = t.attitude(1), psi = 0.3;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d axis = R.col(2);
  const Eigen::Vector3d specific = sigma + test::default_config().vehicle.gravity * Eigen::Vector3d::UnitZ();
  EXPECT_LT(axis.cross(specific.normalized()).norm(), 1e-6);
  EXPECT_GT(axis.dot(specific), 0.0);
  EXPECT_GT(std::abs(theta), 2e-3);  // it really leans (-0.0023 rad here): the test is not vacuous
}

}  // namespace
}  // namespace tmpc
