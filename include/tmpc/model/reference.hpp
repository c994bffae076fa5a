// Helix reference of thesis section 6.2 and the feedforward input (5.4).
//   x_r = cx + r cos(w t), y_r = cy + r sin(w t), z_r = z0 - a cos(w t), psi_r const;
//   phi, theta, gamma, alpha: the trim for the helix's acceleration (default) or the
//   hover equilibrium (thesis-literal); their rates are zero (quasi-static).
//   u_r = L_in(q_r)^# (M(q_r) q_r'' + [C(q_r, q_r') + L_fr] q_r' + G(q_r))      (5.4)
#pragma once

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/equilibrium.hpp"

namespace tmpc {

/// Reference configuration, velocity and acceleration at one time.
struct ReferencePoint {
  Vec10 q = Vec10::Zero();
  Vec10 qd = Vec10::Zero();
  Vec10 qdd = Vec10::Zero();
  /// sigma = reference acceleration of the load (the LPV parameter, thesis (5.8)).
  Eigen::Vector3d sigma() const { return qdd.head<3>(); }
};

class HelixTrajectory {
 public:
  /// Solves the hover equilibrium of `model`; `model` must outlive the trajectory.
  HelixTrajectory(const HelixReference& helix, const TiltrotorModel& model);

  ReferencePoint at(double t) const;
  const HelixReference& helix() const { return helix_; }
  const Equilibrium& equilibrium() const { return equilibrium_; }

 private:
  HelixReference helix_;
  const TiltrotorModel* model_;
  Equilibrium equilibrium_;
};

/// Feedforward u_r of (5.4) by the pseudo-inverse of L_in.
Eigen::Vector4d feedforward(const TiltrotorModel& model, const ReferencePoint& r);

}  // namespace tmpc
