// What a plant needs of the design: the model (the tiltrotor's vehicle or the linear
// model's matrices), its RK4 step and its measured states' kinds; built from a design
// config (the plant process) or the artifact's records (the mission and HIL), then a
// scenario's plant: the vehicle scaled by its factors and a Monte Carlo run's draw, its
// disturbance profile, the start on the reference plus the scenario's offset.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/sim/plant.hpp"
#include "tmpc/sim/scenario.hpp"

namespace tmpc {

struct PlantModel {
  ModelKind kind = ModelKind::Tiltrotor;
  VehicleParams vehicle;
  Eigen::MatrixXd A, B, D;       ///< linear model
  double substep = 0.001;
  std::vector<StateKind> kinds;  ///< of the measured states
  static PlantModel from_config(const Config& cfg);
};

/// The scenario's plant for run `run` (-1: no Monte Carlo draw; seed < 0: the
/// scenario's), `plant_kind` overriding the scenario's model when not empty; started on
/// the reference x_r0 (the measured states at t = 0) plus the scenario's start offset.
std::unique_ptr<Plant> make_scenario_plant(const PlantModel& m, const Scenario& s, const Eigen::VectorXd& x_r0, int run = -1,
                                           long seed = -1, const std::string& plant_kind = "");

}  // namespace tmpc
