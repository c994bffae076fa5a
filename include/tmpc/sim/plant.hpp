// Plant interface for closed-loop work: a simulation that holds the input over a
// period and integrates, sized by its model (the tiltrotor: x = (q, q'), 20 states and
// 4 inputs; a linear model: its own). Implementations: the Euler-Lagrange plant
// (el_plant), the MuJoCo plant when built, and the linear plant (linear_plant).
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/perturbation.hpp"
#include "tmpc/sim/disturbance.hpp"

namespace tmpc {

class Plant {
 public:
  virtual ~Plant() = default;
  virtual int states() const = 0;
  virtual int inputs() const = 0;
  /// Set the state (states() entries) and the clock.
  virtual void reset(const Eigen::VectorXd& x0, double t0) = 0;
  /// Hold u (inputs() entries) for dt seconds and integrate.
  virtual void advance(const Eigen::VectorXd& u, double dt) = 0;
  virtual const Eigen::VectorXd& state() const = 0;
  virtual double time() const = 0;
  /// Force on the load currently applied (N, inertial axes).
  virtual Eigen::Vector3d disturbance() const = 0;
  virtual std::string name() const = 0;
};

/// The tiltrotor plant by name ("el" or "mujoco") for the vehicle `p`, the disturbance
/// profile and the RK4 sub-step. Throws std::invalid_argument for an unknown name or
/// MuJoCo in a build without it.
std::unique_ptr<Plant> make_tiltrotor_plant(const std::string& kind, const VehicleParams& p, DisturbanceProfile d,
                                            double substep);

/// A linear plant x' = A x + B u + D d, exactly discretized per advance (ZOH); d is the
/// first D.cols() components of the profile's load force.
std::unique_ptr<Plant> make_linear_plant(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                                         DisturbanceProfile d);

}  // namespace tmpc
