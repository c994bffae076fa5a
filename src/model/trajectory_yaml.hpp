// Internal: a `trajectory:` section of a scenario file (sim/scenario.cpp) or of a file
// the design envelope names (error_model.cpp), checked like the config:
//   {type: helix, center: [cx, cy, z0], radius, z_amplitude, angular_rate, yaw}
//   {type: hover, position: [x, y, z], yaw}
//   {type: circle, center: [x, y, z], radius, angular_rate, yaw}
//   {type: figure_eight, center: [x, y, z], amplitude: [ax, ay], angular_rate, yaw}
//   {type: waypoints, points: [[x, y, z], ...], max_speed, max_acceleration, yaw}
//   {type: csv, file: PATH}   (relative to the scenario file's folder)
#pragma once

#include <memory>
#include <string>

#include "tmpc/model/trajectory.hpp"
#include "yaml_section.hpp"

namespace tmpc::detail {

/// Throws ConfigError naming the file and the key (a bad CSV: its line).
std::unique_ptr<Trajectory> trajectory_from(Section s, const std::string& base_dir);

/// The folder of a file path ("" for a bare name).
std::string folder_of(const std::string& path);

}  // namespace tmpc::detail
