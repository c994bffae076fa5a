// Hover equilibrium (thesis 5.1, "x_s' = 0"): with phi = theta = 0 and a given yaw,
// find (gamma_1, gamma_2, alpha_r, alpha_l) and u = (f_r, f_l, tau_r, tau_l) with
//   L_in(q) u - G(q) = 0     (10 equations, 8 unknowns; consistent by symmetry)
// by Gauss-Newton with exact Jacobians. Thesis values: gamma_1 = 1.3170e-4,
// gamma_2 = 0.01396, alpha_r = 0.0140, alpha_l = 0.0138 rad.
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

}  // namespace tmpc
