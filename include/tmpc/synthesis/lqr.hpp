// Discrete LQR: P = A'PA - A'PB (R + B'PB)^-1 B'PA + Q (DARE), K = -(R + B'PB)^-1 B'PA,
// u = K x. Solved by the structure-preserving doubling algorithm (quadratic
// convergence); the residual of the DARE is returned so callers can check it.
#pragma once

#include <Eigen/Core>

namespace tmpc {

struct LqrResult {
  Eigen::MatrixXd P;  ///< stabilizing DARE solution (also a terminal cost)
  Eigen::MatrixXd K;  ///< u = K x
  double residual = 0.0;          ///< ||DARE(P)||_F / ||P||_F
  double spectral_radius = 0.0;   ///< of A + B K
  int iterations = 0;
};

/// Throws std::runtime_error when the doubling iteration does not converge
/// (e.g. (A, B) not stabilizable).
LqrResult solve_dlqr(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                     const Eigen::MatrixXd& R);

double spectral_radius(const Eigen::MatrixXd& A);

}  // namespace tmpc
