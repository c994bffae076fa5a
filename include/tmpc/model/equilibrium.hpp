// Equilibrium and trim of the tiltrotor (thesis 5.1, "x_s' = 0", and 5.2).
//
// Hover equilibrium: with phi = theta = 0 and a given yaw, find
// (gamma_1, gamma_2, alpha_r, alpha_l) and u with L_in(q) u - G(q) = 0 (10
// equations, 8 unknowns, consistent by symmetry). Thesis values: gamma_1 =
// 1.3170e-4, gamma_2 = 0.01396, alpha_r = 0.0140, alpha_l = 0.0138 rad.
//
// Trim along a trajectory: for a load acceleration sigma and velocity v, find
// (phi, theta, gamma, alpha) and u with
//   M(q) q_r'' + C(q, q_r') q_r' + L_fr q_r' + G(q) = L_in(q) u,
//   q_r'' = (sigma, 0), q_r' = (v, 0)                 (10 equations, 10 unknowns)
// i.e. the attitude that makes (5.4) exact. At sigma = 0, v = 0 it is the hover
// equilibrium. Both solved by Gauss-Newton with exact (AD) Jacobians.
#pragma once

#include <Eigen/Core>

#include "tmpc/model/dynamics.hpp"

namespace tmpc {

struct Equilibrium {
  Eigen::Vector4d angles = Eigen::Vector4d::Zero();  ///< gamma_1, gamma_2, alpha_r, alpha_l (rad)
  Eigen::Vector4d u = Eigen::Vector4d::Zero();       ///< f_r, f_l (N), tau_r, tau_l (N m)
  double residual = 0.0;                             ///< ||L_in u - G||_inf at the solution
  int iterations = 0;
  Vec10 q() const;                                   ///< configuration at x = y = z = 0
};

/// Throws std::runtime_error when Gauss-Newton does not reach `tolerance`.
Equilibrium solve_hover_equilibrium(const TiltrotorModel& model, double yaw = 0.0, double tolerance = 1e-10);

struct Trim {
  Eigen::Vector2d attitude = Eigen::Vector2d::Zero();  ///< phi, theta of the load frame (rad)
  Eigen::Vector4d angles = Eigen::Vector4d::Zero();    ///< gamma_1, gamma_2, alpha_r, alpha_l (rad)
  Eigen::Vector4d u = Eigen::Vector4d::Zero();
  double residual = 0.0;
  int iterations = 0;
};

/// Trim for load acceleration `sigma` and velocity `velocity` at yaw `yaw`,
/// starting from `start` (e.g. the hover equilibrium, or a neighbouring trim). Throws
/// std::runtime_error when it fails.
Trim solve_trim(const TiltrotorModel& model, const Eigen::Vector3d& sigma, const Eigen::Vector3d& velocity,
                double yaw, const Trim& start, double tolerance = 1e-10);
/// The same without throwing: false (and `out` untouched) when it does not converge.
/// No allocation: the real-time path's version.
bool try_solve_trim(const TiltrotorModel& model, const Eigen::Vector3d& sigma, const Eigen::Vector3d& velocity,
                    double yaw, const Trim& start, Trim& out, double tolerance = 1e-10);
/// The hover equilibrium as a trim's start point (zero attitude).
Trim trim_start(const Equilibrium& e);
Trim solve_trim(const TiltrotorModel& model, const Eigen::Vector3d& sigma, const Eigen::Vector3d& velocity,
                double yaw, const Equilibrium& start, double tolerance = 1e-10);

}  // namespace tmpc
