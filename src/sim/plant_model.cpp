// Scenario plants (see plant_model.hpp).
#include "tmpc/sim/plant_model.hpp"

#include <stdexcept>

namespace tmpc {

PlantModel PlantModel::from_config(const Config& cfg) {
  PlantModel m;
  m.kind = cfg.model;
  m.vehicle = cfg.vehicle;
  m.A = cfg.linear.A;
  m.B = cfg.linear.B;
  m.D = cfg.linear.D;
  m.substep = cfg.simulation.substep;
  const std::vector<StateKind> all = cfg.state_kinds();
  m.kinds.assign(all.begin(), all.begin() + cfg.measured());
  return m;
}

std::unique_ptr<Plant> make_scenario_plant(const PlantModel& m, const Scenario& s, const Eigen::VectorXd& x_r0, int run,
                                           long seed, const std::string& plant_kind) {
  std::unique_ptr<Plant> p;
  if (m.kind == ModelKind::Tiltrotor) {
    p = make_tiltrotor_plant(plant_kind.empty() ? s.plant.model : plant_kind, s.plant_vehicle(m.vehicle, run, seed),
                             s.disturbances, m.substep);
  } else {
    if (run >= 0 || !plant_kind.empty()) {
      throw std::invalid_argument("a linear plant has no masses to perturb and no other physics engine");
    }
    p = make_linear_plant(m.A, m.B, m.D, s.disturbances);
  }
  if (!s.faults.empty()) {
    try {
      p = with_actuator_faults(std::move(p), s.faults);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(s.source + ": " + e.what());
    }
  }
  Eigen::VectorXd x0 = x_r0;
  // The start offset: position (the first three position states) and yaw.
  int pos = 0;
  for (std::size_t i = 0; i < m.kinds.size(); ++i) {
    if (m.kinds[i] == StateKind::Position && pos < 3) x0(static_cast<Eigen::Index>(i)) += s.start_position_offset(pos++);
    if (m.kinds[i] == StateKind::Yaw) x0(static_cast<Eigen::Index>(i)) += s.start_yaw_offset;
  }
  p->reset(x0, 0.0);
  return p;
}

}  // namespace tmpc
