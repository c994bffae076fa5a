// Euler-Lagrange plant: energy conservation (energy from finite differences of the
// kinematics, not from M), hover at rest, and the feedforward keeping the plant on
// the helix.
#include <gtest/gtest.h>

#include "../model/test_support.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/sim/el_plant.hpp"

namespace tmpc {
namespace {

/// Kinetic + potential energy from body poses only: velocities by central
/// differences of positions and rotations along q'.
double energy_from_kinematics(const KinematicTree& tree, double g, const State20& x) {
  const Vec10 q = x.head<kNq>(), qd = x.tail<kNq>();
  const double h = 1e-6;
  const Vec10 qp = q + h * qd, qm = q - h * qd;
  const TreePose<double> p0 = tree.pose(q.data()), pp = tree.pose(qp.data()), pm = tree.pose(qm.data());
  double e = 0.0;
  for (const TreeBody& b : tree.bodies()) {
    const auto f = static_cast<std::size_t>(b.frame);
    const Eigen::Vector3d c0 = p0.p[f] + p0.R[f] * b.com;
    const Eigen::Vector3d v = ((pp.p[f] + pp.R[f] * b.com) - (pm.p[f] + pm.R[f] * b.com)) / (2 * h);
    const Eigen::Matrix3d W = p0.R[f].transpose() * (pp.R[f] - pm.R[f]) / (2 * h);  // body rates, skew
    const Eigen::Vector3d w(W(2, 1), W(0, 2), W(1, 0));
    e += 0.5 * b.mass * v.squaredNorm() + 0.5 * w.dot(b.inertia * w) + b.mass * g * c0.z();
  }
  return e;
}

TEST(ElPlant, ConservesEnergyWithoutDragInputOrDisturbance) {
  VehicleParams p = test::default_config().vehicle;
  p.friction.fill(0.0);
  ElPlant plant(p, DisturbanceProfile{}, 0.001);
  const KinematicTree tree(p);
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 3; ++trial) {
    State20 x0;
    x0 << test::random_q(rng), test::random_qd(rng);
    plant.reset(x0, 0.0);
    const double e0 = energy_from_kinematics(tree, p.gravity, x0);
    double drift = 0.0;
    for (int k = 0; k < 5000; ++k) {
      plant.advance(Eigen::Vector4d::Zero(), 0.001);
      const double e = energy_from_kinematics(tree, p.gravity, plant.state());
      drift = std::max(drift, std::abs(e - e0));
    }
    // Relative to the energy exchanged (kinetic energy reached in the fall).
    const double t_end = plant.model().kinetic_energy(plant.state().head<kNq>(), plant.state().tail<kNq>());
    EXPECT_LT(drift / t_end, 1e-6) << "trial " << trial << " drift " << drift << " J of " << t_end << " J";
  }
}

TEST(ElPlant, StaysAtTheHoverEquilibrium) {
  const Config& cfg = test::default_config();
  ElPlant plant(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  const Equilibrium eq = solve_hover_equilibrium(plant.model());
  State20 x0;
  x0 << eq.q(), Vec10::Zero();
  plant.reset(x0, 0.0);
  for (int k = 0; k < 100; ++k) plant.advance(eq.u, cfg.sample_time);
  EXPECT_NEAR(plant.time(), 1.2, 1e-12);
  EXPECT_LT((plant.state() - x0).cwiseAbs().maxCoeff(), 1e-8);
}

/// Largest distance of the load from the helix over 2 s of open-loop feedforward.
double feedforward_drift(const Config& cfg) {
  auto plant = make_tiltrotor_plant("el", cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator traj(model, test::thesis_helix(), cfg.attitude);
  State20 x0;
  const ReferencePoint r0 = traj.at(0.0);
  x0 << r0.q, r0.qd;
  plant->reset(x0, 0.0);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    plant->advance(feedforward(model, traj.at(plant->time())), 0.001);
    const ReferencePoint r = traj.at(plant->time());
    worst = std::max(worst, (plant->state().head<3>() - r.q.head<3>()).norm());
  }
  return worst;
}

TEST(ElPlant, FeedforwardKeepsThePlantOnTheHelixFor2s) {
  const double drift = feedforward_drift(test::default_config());
  EXPECT_LT(drift, 0.01) << "load position left the helix by " << drift << " m";
}

TEST(ElPlant, ThesisLiteralReferenceAttitudeLeavesTheHelix) {
  // Documented deviation: holding phi, theta, gamma, alpha at the hover equilibrium
  // while the load accelerates makes (5.4) a least-squares fit; its residual drives
  // the open-loop plant off the helix. This is why the trim attitude is the default.
  Config cfg = test::default_config();
  cfg.attitude = ReferenceAttitude::Equilibrium;
  EXPECT_GT(feedforward_drift(cfg), 0.1);
}

TEST(ElPlant, RejectsUnknownPlantKinds) {
  EXPECT_THROW(make_tiltrotor_plant("gazebo", test::default_config().vehicle, DisturbanceProfile{}, 0.001),
               std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
