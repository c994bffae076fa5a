#include "tmpc/sim/el_plant.hpp"

#include <cmath>
#include <stdexcept>


namespace tmpc {

ElPlant::ElPlant(const VehicleParams& params, DisturbanceSchedule disturbance, double substep)
    : model_(params), disturbance_(std::move(disturbance)), substep_(substep) {
  if (!(substep > 0.0)) throw std::invalid_argument("ElPlant: substep must be positive");
}

void ElPlant::reset(const State20& x0, double t0) {
  x_ = x0;
  t_ = t0;
}

void ElPlant::advance(const Eigen::Vector4d& u, double dt) {
  const long n = std::max(1L, static_cast<long>(std::llround(dt / substep_)));
  const double h = dt / static_cast<double>(n);
  for (long i = 0; i < n; ++i) {
    // The disturbance is constant over a sub-step, taken at its midpoint, so a step
    // at a sub-step boundary switches cleanly (and both plants agree).
    const Eigen::Vector3d d = disturbance_.force(t_ + 0.5 * h);
    const State20 k1 = model_.state_derivative(x_, u, d);
    const State20 k2 = model_.state_derivative(x_ + 0.5 * h * k1, u, d);
    const State20 k3 = model_.state_derivative(x_ + 0.5 * h * k2, u, d);
    const State20 k4 = model_.state_derivative(x_ + h * k3, u, d);
    x_ += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    t_ += h;
  }
}

}  // namespace tmpc
