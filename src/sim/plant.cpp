// Plant factory: the tiltrotor plant named by the scenario or the command line.
#include <stdexcept>

#include "tmpc/sim/el_plant.hpp"
#include "tmpc/sim/mujoco_plant.hpp"

namespace tmpc {

std::unique_ptr<Plant> make_tiltrotor_plant(const std::string& kind, const VehicleParams& p, DisturbanceProfile d,
                                            double substep) {
  if (kind == "el") return std::make_unique<ElPlant>(p, std::move(d), substep);
  if (kind == "mujoco") {
#ifdef TMPC_HAVE_MUJOCO
    return std::make_unique<MujocoPlant>(p, std::move(d), substep);
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
