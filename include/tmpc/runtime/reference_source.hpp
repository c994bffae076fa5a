// The reference the runtime tracks, from the artifact's plant model: the measured
// states' reference x_r and the feedforward u_r at time t.
//   tiltrotor: the trajectory's position and yaw with the trimmed attitude (model/
//              reference.hpp) and the feedforward (5.4), with the vehicle of the
//              artifact's records; each trim warm-started from the previous call's
//   linear:    the origin, u_r = 0 (regulation; its trajectory must hover at the origin)
// at() allocates nothing after construction.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "tmpc/model/trajectory.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

class ReferenceSource {
 public:
  virtual ~ReferenceSource() = default;
  /// x_r (the measured states) and u_r (the inputs) at t, into sized vectors; false
  /// where the reference does not exist (no trim: a trajectory outside the envelope,
  /// which the pre-flight check refuses). Never throws.
  virtual bool at(double t, Eigen::VectorXd& x_r, Eigen::VectorXd& u_r) = 0;
  /// The hover input (the safe command before any state): tiltrotor hover, linear 0.
  virtual const Eigen::VectorXd& hover_input() const = 0;
};

/// Throws std::invalid_argument when the trajectory does not fit the model (a linear
/// model's trajectory must hover at the origin).
std::unique_ptr<ReferenceSource> make_reference_source(const ControllerArtifact& a,
                                                       std::shared_ptr<const Trajectory> trajectory);
/// The same from the parts of a design config (the plant process has no artifact).
std::unique_ptr<ReferenceSource> make_reference_source(ModelKind kind, const VehicleParams& vehicle,
                                                       ReferenceAttitude attitude, int inputs,
                                                       std::shared_ptr<const Trajectory> trajectory);

}  // namespace tmpc
