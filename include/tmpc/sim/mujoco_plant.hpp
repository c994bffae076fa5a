// Independent physics plant on MuJoCo (model spec section 8). The MJCF is
// generated from the same vehicle parameters as the Euler-Lagrange model:
//   load body with a free joint (mass, inertia), child "main" at (0, 0, l) + dA1B
//   with the hinges gamma_1 (axis -x) then gamma_2 (axis -y) at -dA1B (= A1),
//   body inertia at dB1, rotor bodies at dB2 / dB3 rolled by Rx(-+beta) with a
//   y-axis hinge each, CoM at c; thrust and rotor drag torque as site actuators
//   (gear 0 0 1 0 0 +-k_tau/b), servo torques as joint motors, joint damping mu,
//   the disturbances as world forces on the load and the main body (xfrc_applied).
// Only physical inertias are accepted (S2 is not a rigid body; MuJoCo rejects it).
#pragma once

#include <memory>
#include <string>

#include "tmpc/model/dynamics.hpp"
#include "tmpc/sim/disturbance.hpp"
#include "tmpc/sim/plant.hpp"

namespace tmpc {

/// MJCF text for the vehicle; `timestep` is MuJoCo's RK4 step. Throws
/// std::invalid_argument for parameters MuJoCo cannot represent (S2, friction on
/// the free joint).
std::string make_mjcf(const VehicleParams& params, double timestep);

/// Whether this build has the MuJoCo plant (TMPC_WITH_MUJOCO).
bool mujoco_available();

class MujocoPlant final : public Plant {
 public:
  MujocoPlant(const VehicleParams& params, DisturbanceProfile disturbance, double substep);
  ~MujocoPlant() override;
  MujocoPlant(const MujocoPlant&) = delete;
  MujocoPlant& operator=(const MujocoPlant&) = delete;

  int states() const override { return kNx; }
  int inputs() const override { return kNu; }
  void reset(const Eigen::VectorXd& x0, double t0) override;
  void advance(const Eigen::VectorXd& u, double dt) override;
  const Eigen::VectorXd& state() const override;
  double time() const override;
  Eigen::Vector3d disturbance() const override;
  std::string name() const override { return "mujoco"; }

  /// MuJoCo's forward dynamics at x with input u and load force d, mapped to our q''.
  Vec10 acceleration(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d);
  /// MuJoCo library version, e.g. "2.2.2".
  static std::string version();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tmpc
