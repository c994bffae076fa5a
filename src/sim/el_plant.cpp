#include "tmpc/sim/el_plant.hpp"

#include <cmath>
#include <stdexcept>

namespace tmpc {

ElPlant::ElPlant(const VehicleParams& params, DisturbanceProfile disturbance, double substep)
    : model_(params), disturbance_(std::move(disturbance)), substep_(substep) {
  if (!(substep > 0.0)) throw std::invalid_argument("ElPlant: substep must be positive");
}

void ElPlant::reset(const Eigen::VectorXd& x0, double t0) {
  if (x0.size() != kNx) throw std::invalid_argument("ElPlant: reset with " + std::to_string(x0.size()) + " states, expected 20");
  x_ = x0;
  state_ = x0;
  t_ = t0;
}

void ElPlant::advance(const Eigen::VectorXd& u_in, double dt) {
  const Eigen::Vector4d u = u_in.head<kNu>();
  const long n = std::max(1L, static_cast<long>(std::llround(dt / substep_)));
  const double h = dt / static_cast<double>(n);
  for (long i = 0; i < n; ++i) {
    // The disturbance is constant over a sub-step, taken at its midpoint, so a step
    // at a sub-step boundary switches cleanly (and both plants agree).
    const double tm = t_ + 0.5 * h;
    x_ = rk4_step(model_, x_, u, disturbance_.load_force(tm), disturbance_.body_force(tm), h);
    t_ += h;
  }
  state_ = x_;
}

}  // namespace tmpc
