#include "tmpc/sim/el_plant.hpp"

#include <cmath>
#include <stdexcept>

#include "tmpc/sim/perturbation.hpp"

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
  const int n = std::max(1, static_cast<int>(std::ceil(dt / substep_ - 1e-9)));
  const double h = dt / n;
  for (int i = 0; i < n; ++i) {
    const double t = t_;
    const State20 k1 = model_.state_derivative(x_, u, disturbance_.force(t));
    const State20 k2 = model_.state_derivative(x_ + 0.5 * h * k1, u, disturbance_.force(t + 0.5 * h));
    const State20 k3 = model_.state_derivative(x_ + 0.5 * h * k2, u, disturbance_.force(t + 0.5 * h));
    const State20 k4 = model_.state_derivative(x_ + h * k3, u, disturbance_.force(t + h));
    x_ += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    t_ = t + h;
  }
}

std::unique_ptr<Plant> make_plant(const std::string& kind, const Config& cfg, bool with_disturbance, int run) {
  VehicleParams params = cfg.vehicle;
  if (run >= 0) params = apply_mass_scaling(params, draw_mass_scaling(cfg.perturbation, run));
  DisturbanceSchedule schedule(with_disturbance ? cfg.disturbances : std::vector<DisturbanceStep>{});
  if (kind == "el") return std::make_unique<ElPlant>(params, std::move(schedule), cfg.simulation.substep);
  throw std::invalid_argument("unknown plant '" + kind + "' (available: el)");
}

}  // namespace tmpc
