// Hover equilibrium and feedforward: the thesis equilibrium (section 6.2) is
// reproduced, and u_r of (5.4) is the equilibrium input at hover.
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
  const HelixTrajectory traj(cfg.reference, solve_hover_equilibrium(model).angles);
  const ReferencePoint r0 = traj.at(0.0);
  EXPECT_NEAR(r0.q(kX), 5.0, 1e-12);
  EXPECT_NEAR(r0.q(kY), 0.0, 1e-12);
  EXPECT_NEAR(r0.q(kZ), 1.0, 1e-12);  // E8: z_r(0) = 4 - 3 = 1 m
  // Derivatives against central differences of the positions.
  const double t = 13.7, h = 1e-5;
  const ReferencePoint r = traj.at(t);
  const Vec10 v = (traj.at(t + h).q - traj.at(t - h).q) / (2 * h);
  const Vec10 a = (traj.at(t + h).qd - traj.at(t - h).qd) / (2 * h);
  EXPECT_LT((r.qd - v).norm(), 1e-8);
  EXPECT_LT((r.qdd - a).norm(), 1e-8);
}

}  // namespace
}  // namespace tmpc
