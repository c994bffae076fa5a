// A scenario: one flight, apart from the design config (DESIGN.md 2). YAML:
//   name: thesis_helix                      (optional; the file's name otherwise)
//   duration: 80                            s (a finite trajectory's length at most)
//   trajectory: {type: helix, ...}          (model/trajectory.hpp; the linear model: hover at 0)
//   start_offset: {position: [0, 0, 0], yaw: 0}   (optional) the plant starts this far off
//   disturbances:                           (optional) forces, inertial axes (sim/disturbance.hpp)
//     - {type: step, time: 20, force: [1, 0, 0], on: load}
//     - {type: ramp, start: 10, end: 20, force: [0, 0.5, 0], on: body}
//     - {type: sine, start: 0, end: 30, amplitude: [0.3, 0, 0], frequency: 0.5, phase: 0}
//     - {type: gust, start: 0, magnitude: 1.5, time_constant: 1, redraw: 8, seed: 3,
//        horizontal: false, on: load}
//   noise:                                  (optional) sensor noise (sim/noise.hpp)
//     {seed: 4, position: {white: 0.005, bias: 0}, angle: {white: 0.0052},
//      velocity: {white: 0.01}, angular_rate: {white: 0.02}}
//   faults:                                 (optional) actuator faults (sim/actuator_fault.hpp)
//     - {type: efficiency, input: 0, factor: 0.9, start: 30, end: 60}
//     - {type: bias, input: 2, value: 0.01, start: 20}
//     - {type: stuck, input: 3, start: 40}
//   plant:                                  (optional)
//     model: el | mujoco                    (the tiltrotor's plant)
//     scale: {load_mass: 1, load_inertia: 1, body_mass: 1, body_inertia: 1,
//             rotor_mass: 1, rotor_inertia: 1}          explicit factors, or
//     random: {fraction: 0.1, distribution: uniform, seed: 7, runs: 10}  (Monte Carlo)
// Every key is checked: unknown keys, bad values and a bad CSV are errors naming the
// file and the key (or the CSV's line).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/perturbation.hpp"
#include "tmpc/model/trajectory.hpp"
#include "tmpc/sim/actuator_fault.hpp"
#include "tmpc/sim/disturbance.hpp"
#include "tmpc/sim/noise.hpp"

namespace tmpc {

struct PlantSpec {
  std::string model = "el";
  MassScaling scale;                 ///< explicit factors (1: nominal)
  PerturbationSettings random;       ///< Monte Carlo draws (fraction 0: none)
};

struct Scenario {
  std::string name, source;
  double duration = 0.0;
  std::shared_ptr<const Trajectory> trajectory;
  Eigen::Vector3d start_position_offset = Eigen::Vector3d::Zero();
  double start_yaw_offset = 0.0;
  DisturbanceProfile disturbances;
  NoiseSpec noise;
  std::vector<ActuatorFault> faults;  ///< in the plant, on the input it is sent
  PlantSpec plant;
  /// The vehicle of a run: `p` scaled by the explicit factors, then (run >= 0) by Monte
  /// Carlo run `run`'s draw (seed: `seed` >= 0, else the scenario's).
  VehicleParams plant_vehicle(const VehicleParams& p, int run = -1, long seed = -1) const;
};

/// Throws ConfigError naming the file and the key.
Scenario load_scenario(const std::string& path);
Scenario scenario_from_string(const std::string& yaml, const std::string& source, const std::string& base_dir = "");

}  // namespace tmpc
