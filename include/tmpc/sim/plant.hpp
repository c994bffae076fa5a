// Plant interface for closed-loop work: a vehicle simulation that holds the input
// over a period and integrates. Implementations: the Euler-Lagrange plant (el_plant)
// and, when built, the MuJoCo plant. The state is x = (q, q') in the model's order.
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/dynamics.hpp"

namespace tmpc {

class Plant {
 public:
  virtual ~Plant() = default;
  /// Set the state and the clock.
  virtual void reset(const State20& x0, double t0) = 0;
  /// Hold u (f_r, f_l, tau_r, tau_l) for dt seconds and integrate.
  virtual void advance(const Eigen::Vector4d& u, double dt) = 0;
  virtual const State20& state() const = 0;
  virtual double time() const = 0;
  /// Disturbance force on the load currently applied (N, inertial axes).
  virtual Eigen::Vector3d disturbance() const = 0;
  virtual std::string name() const = 0;
};

/// Plant by name ("el"), with the config's disturbance schedule when
/// `with_disturbance` and the masses/inertias of Monte Carlo run `run` (-1: nominal).
std::unique_ptr<Plant> make_plant(const std::string& kind, const Config& cfg, bool with_disturbance, int run);

}  // namespace tmpc
