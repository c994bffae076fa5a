// Plant factory: the plant named by config or command line, with the disturbance
// schedule and the Monte Carlo mass/inertia scaling of a run.
#include <stdexcept>

#include "tmpc/sim/el_plant.hpp"
#include "tmpc/sim/mujoco_plant.hpp"
#include "tmpc/sim/perturbation.hpp"

namespace tmpc {

std::unique_ptr<Plant> make_plant(const std::string& kind, const Config& cfg, bool with_disturbance, int run) {
  VehicleParams params = cfg.vehicle;
  if (run >= 0) params = apply_mass_scaling(params, draw_mass_scaling(cfg.perturbation, run));
  DisturbanceSchedule schedule(with_disturbance ? cfg.disturbances : std::vector<DisturbanceStep>{});
  if (kind == "el") return std::make_unique<ElPlant>(params, std::move(schedule), cfg.simulation.substep);
  if (kind == "mujoco") {
#ifdef TMPC_HAVE_MUJOCO
    return std::make_unique<MujocoPlant>(params, std::move(schedule), cfg.simulation.substep);
#else
    throw std::invalid_argument("plant 'mujoco': this build has no MuJoCo (install libmujoco-dev and rebuild with "
                                "TMPC_WITH_MUJOCO=AUTO or ON)");
#endif
  }
  throw std::invalid_argument("unknown plant '" + kind + "' (available: el, mujoco)");
}

#ifndef TMPC_HAVE_MUJOCO
bool mujoco_available() { return false; }
#endif

}  // namespace tmpc
