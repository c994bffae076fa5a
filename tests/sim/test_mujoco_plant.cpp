// The MuJoCo plant against the Euler-Lagrange model: forward dynamics at 1,000
// random admissible states and inputs, hover, and open-loop agreement.
#include <cstdio>
#include <functional>

#include <gtest/gtest.h>

#include "../model/test_support.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/perturbation.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/sim/el_plant.hpp"
#include "tmpc/sim/mujoco_plant.hpp"

namespace tmpc {
namespace {

TEST(MujocoPlant, ForwardDynamicsMatchTheModelAt1000States) {
  const Config& cfg = test::default_config();
  MujocoPlant mj(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  const TiltrotorModel model(cfg.vehicle);
  std::mt19937_64 rng(31);
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    State20 x;
    x << test::random_q(rng), test::random_qd(rng);
    const Eigen::Vector4d u = test::random_u(rng);
    const Eigen::Vector3d d = Eigen::Vector3d::Random();
    const Vec10 ours = model.acceleration(x.head<kNq>(), x.tail<kNq>(), u, d);
    const Vec10 theirs = mj.acceleration(x, u, d);
    worst = std::max(worst, (ours - theirs).norm() / ours.norm());
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  std::printf("forward dynamics, worst relative difference over 1000 states: %.3e\n", worst);
  EXPECT_LT(worst, 1e-10);  // README: two engines agree to a few 1e-11
}

TEST(MujocoPlant, HoverAccelerationsAreSmall) {
  const Config& cfg = test::default_config();
  MujocoPlant mj(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle));
  State20 x;
  x << eq.q(), Vec10::Zero();
  EXPECT_LT(mj.acceleration(x, eq.u, Eigen::Vector3d::Zero()).cwiseAbs().maxCoeff(), 1e-12);
  // The thesis equilibrium angles as published with the vehicle code (model spec:
  // equil_g1 = 1.316967e-4, ...) with the hover inputs: below 1e-3.
  State20 xt = State20::Zero();
  xt.segment<4>(kGamma1) << 1.316967e-4, 0.0139602, 0.0140053, 0.0138091;
  const double acc = mj.acceleration(xt, eq.u, Eigen::Vector3d::Zero()).cwiseAbs().maxCoeff();
  std::printf("hover at the thesis equilibrium angles: max |q''| = %.3e\n", acc);
  EXPECT_LT(acc, 1e-3);
  // With the thesis' published inputs too, tau_l = 1.0121e-5 N m is 5e-7 N m short
  // of what the S1 geometry needs (1.066e-5, as the model spec's own solve finds);
  // on the light tilt joints such gaps give 1e-3 to 2e-3 rad/s^2. Asserted so it is not hidden.
  const Eigen::Vector4d ut(11.732257, 11.767602, 4.1389e-7, 1.0121e-5);
  const Vec10 qdd = mj.acceleration(xt, ut, Eigen::Vector3d::Zero());
  std::printf("with the thesis' published hover inputs: max |q''| = %.3e (alpha_l)\n", qdd.cwiseAbs().maxCoeff());
  EXPECT_LT(qdd.head<kAlphaR>().cwiseAbs().maxCoeff(), 1e-3);  // all but the tilt joints
  EXPECT_LT(qdd.tail<2>().cwiseAbs().maxCoeff(), 3e-3);
}

/// Largest position (m) and angle (rad) difference between the two plants.
std::pair<double, double> compare(Plant& a, Plant& b, const State20& x0, double duration,
                                  const std::function<Eigen::Vector4d(double)>& input) {
  a.reset(x0, 0.0);
  b.reset(x0, 0.0);
  double dp = 0.0, da = 0.0;
  const double dt = 0.001;
  const int n = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector4d u = input(a.time());
    a.advance(u, dt);
    b.advance(u, dt);
    dp = std::max(dp, (a.state().head<3>() - b.state().head<3>()).norm());
    da = std::max(da, (a.state().segment<7>(kPhi) - b.state().segment<7>(kPhi)).cwiseAbs().maxCoeff());
  }
  return {dp, da};
}

TEST(MujocoPlant, OpenLoopAgreementAlongTheHelixAndForAServoStep) {
  const Config& cfg = test::default_config();
  ElPlant el(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  MujocoPlant mj(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator traj(model, test::thesis_helix(), cfg.attitude);
  // Feedforward along the helix for 2 s.
  const ReferencePoint r0 = traj.at(0.0);
  State20 x0;
  x0 << r0.q, r0.qd;
  const auto [dp1, da1] = compare(el, mj, x0, 2.0, [&](double t) { return feedforward(model, traj.at(t)); });
  std::printf("helix feedforward 2 s: position %.3e m, angles %.3e rad\n", dp1, da1);
  EXPECT_LT(dp1, 2e-13);  // README: 9e-14 m
  EXPECT_LT(da1, 1e-13);
  // A step of 0.05 N m in the right servo torque from hover, for 0.5 s.
  const Equilibrium& eq = traj.equilibrium();
  State20 xh;
  xh << eq.q(), Vec10::Zero();
  const Eigen::Vector4d step = eq.u + Eigen::Vector4d(0, 0, 0.05, 0);
  const auto [dp2, da2] = compare(el, mj, xh, 0.5, [&](double) { return step; });
  std::printf("servo torque step 0.5 s: position %.3e m, angles %.3e rad\n", dp2, da2);
  EXPECT_LT(dp2, 7e-7);  // README: 3.6e-7 m, 2.6e-6 rad (the light tilt joints)
  EXPECT_LT(da2, 5e-6);
}

TEST(MujocoPlant, DisturbancesOnTheLoadAndTheBodyAreApplied) {
  const Config& cfg = test::default_config();
  DisturbanceEvent on_body;
  on_body.force = Eigen::Vector3d(0.0, 0.3, 0.0);
  on_body.target = DisturbanceEvent::Target::Body;
  DisturbanceEvent on_load;
  on_load.force = Eigen::Vector3d(1.0, 0.0, 0.0);
  const DisturbanceProfile d({on_load, on_body});
  auto el = make_tiltrotor_plant("el", cfg.vehicle, d, cfg.simulation.substep);
  auto mj = make_tiltrotor_plant("mujoco", cfg.vehicle, d, cfg.simulation.substep);
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle));
  State20 x0;
  x0 << eq.q(), Vec10::Zero();
  const auto [dp, da] = compare(*el, *mj, x0, 0.5, [&](double) { return eq.u; });
  std::printf("1 N on the load and 0.3 N on the body for 0.5 s: position %.3e m, angles %.3e rad\n", dp, da);
  // Measured: 2.8e-10 m, 4.1e-9 rad (the force on the body swings the light tilt
  // joints, whose step response agrees to 2.6e-6 rad above); a force applied at the
  // wrong point (1 mm off the CoM: 3e-4 N m) would differ by orders of magnitude more.
  EXPECT_LT(dp, 1e-9);
  EXPECT_LT(da, 2e-8);
  EXPECT_GT(mj->state()(kX), 1e-3);  // pushed along +x
  EXPECT_GT(mj->state()(kY), 1e-4);  // and along +y by the force on the body
  EXPECT_EQ(mj->disturbance(), Eigen::Vector3d(1, 0, 0));
}

TEST(MujocoPlant, RejectsParameterSetS2WithAReason) {
  VehicleParams p = test::default_config().vehicle;
  p.rotor_inertia_reference = RotorInertiaReference::Pivot;
  try {
    make_mjcf(p, 0.001);
    FAIL() << "S2 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("S2"), std::string::npos) << e.what();
  }
}

TEST(MujocoPlant, PerturbedPlantsDifferFromTheNominal) {
  const Config& cfg = test::default_config();
  auto nominal = make_tiltrotor_plant("mujoco", cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  const PerturbationSettings mc{0.10, "uniform", 1, 10};  // the thesis Monte Carlo, run 3
  auto perturbed = make_tiltrotor_plant("mujoco", apply_mass_scaling(cfg.vehicle, draw_mass_scaling(mc, 3)),
                                        DisturbanceProfile{}, cfg.simulation.substep);
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle));
  State20 x0;
  x0 << eq.q(), Vec10::Zero();
  nominal->reset(x0, 0.0);
  perturbed->reset(x0, 0.0);
  nominal->advance(eq.u, 0.5);
  perturbed->advance(eq.u, 0.5);
  EXPECT_GT((nominal->state() - perturbed->state()).norm(), 1e-4);
  EXPECT_EQ(perturbed->name(), "mujoco");
}

}  // namespace
}  // namespace tmpc
