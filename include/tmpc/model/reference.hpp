// The reference of the tiltrotor along a trajectory (thesis 6.2, generalized) and the
// feedforward input (5.4):
//   q_r = (x, y, z from the trajectory, phi, theta trimmed, psi from the trajectory,
//          gamma, alpha trimmed), q_r' = (v, 0, 0, psi', 0...), q_r'' = (a, 0, 0, psi'', 0...)
//   the trim (default) solves the attitude for the acceleration (equilibrium.hpp) so
//   that (5.4) holds exactly; `equilibrium` holds the hover attitude (thesis-literal)
//   u_r = L_in(q_r)^# (M(q_r) q_r'' + [C(q_r, q_r') + L_fr] q_r' + G(q_r))      (5.4)
#pragma once

#include <memory>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/trajectory.hpp"

namespace tmpc {

/// Reference configuration, velocity and acceleration at one time.
struct ReferencePoint {
  Vec10 q = Vec10::Zero();
  Vec10 qd = Vec10::Zero();
  Vec10 qdd = Vec10::Zero();
  /// sigma = reference acceleration of the load (the LPV parameter, thesis (5.8)).
  Eigen::Vector3d sigma() const { return qdd.head<3>(); }
};

class ReferenceGenerator {
 public:
  /// `model` must outlive the generator. Solves the hover equilibrium at the
  /// trajectory's yaw at t = 0 (throws std::runtime_error if there is none).
  ReferenceGenerator(const TiltrotorModel& model, std::shared_ptr<const Trajectory> trajectory,
                     ReferenceAttitude attitude = ReferenceAttitude::Trim);
  /// The reference at t. Each trim starts from the previous call's (a flight asks for
  /// neighbouring times: one or two Gauss-Newton steps); throws std::runtime_error when
  /// no trim exists (a trajectory outside the envelope: `tmpc check` refuses those).
  ReferencePoint at(double t);
  /// The same without throwing (false where no trim exists); no allocation.
  bool try_at(double t, ReferencePoint& out);
  const Equilibrium& equilibrium() const { return equilibrium_; }
  const Trajectory& trajectory() const { return *trajectory_; }
  std::shared_ptr<const Trajectory> shared_trajectory() const { return trajectory_; }
  const TiltrotorModel& model() const { return *model_; }

 private:
  const TiltrotorModel* model_;
  std::shared_ptr<const Trajectory> trajectory_;
  ReferenceAttitude attitude_;
  Equilibrium equilibrium_;
  Trim last_;
  double last_yaw_ = 0.0;
  bool have_last_ = false;
};

/// Feedforward u_r of (5.4) by the pseudo-inverse of L_in.
Eigen::Vector4d feedforward(const TiltrotorModel& model, const ReferencePoint& r);

}  // namespace tmpc
