// Before any flight (`tmpc check`, and every command that flies): a trajectory is
// flyable with an artifact when, sampled every period over the flight,
//   its acceleration stays inside the artifact's envelope box (the LPV vertices),
//   its speed below the envelope's, its yaw within the envelope's yaw +- tolerance,
//   the trim exists and the feedforward u_r stays inside the range the input box was
//   tightened for (so that u_r + U_bar stays inside the actuator limits),
// and (linear model) it hovers at the origin. A refusal gives the first time and the
// numbers ("figure_eight: t = 3.25 s: acceleration y = 0.84 m/s^2 outside [-0.6, 0.6]").
#pragma once

#include <string>

#include "tmpc/model/trajectory.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct PreflightReport {
  bool ok = true;
  std::string message;   ///< the first violation, or a summary when ok
  double time = 0.0;     ///< of the first violation
  Eigen::Vector3d acceleration_min = Eigen::Vector3d::Zero(), acceleration_max = Eigen::Vector3d::Zero();
  double speed_max = 0.0;
  Eigen::VectorXd feedforward_min, feedforward_max;
};

PreflightReport check_flight(const ControllerArtifact& a, const Trajectory& t, double duration);
/// Throws std::invalid_argument with the report's message when the flight is refused.
void require_flight(const ControllerArtifact& a, const Trajectory& t, double duration, const std::string& what);

}  // namespace tmpc
