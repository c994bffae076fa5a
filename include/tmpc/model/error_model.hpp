// Linear error model of the design (thesis section 5.2), for any model:
//   x_tilde' = A(sigma) x_tilde + B u_tilde + D d                            (5.5)
// Tiltrotor: linearized at the trim for the load's reference acceleration sigma (the
//   LPV parameter, 3 entries), A(sigma) = A_0 + sum_i sigma_i A_i with A_0 at sigma = 0
//   and A_i the secant of A over the envelope's range of sigma_i; vertices at the 8
//   corners of the envelope's box; the feedforward's range over a grid of the box.
// Linear model: A, B, D as configured (LTI: no vertices, u_r = 0).
// Both augmented with the integrals of the configured errors (5.6)-(5.7):
//   A_a = [A 0; C 0], B_a = [B; 0], D_a = [D; 0]
// discrete: exact ZOH (default) or Euler A_z = I + A_a T (thesis (5.8), E1)
// normalized: x_n = N_x x, u_n = N_u u, A_n = N_x A_z N_x^-1, B_n = N_x B_z N_u^-1 (5.10)-(5.11)
// The report says how affine A really is over the envelope: the true A(sigma) at the
// grid points against A_0 + sum sigma_i A_i.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/equilibrium.hpp"

namespace tmpc {

constexpr int kNa = 24;  ///< the tiltrotor's augmented error states

using Mat20 = Eigen::Matrix<double, kNx, kNx>;

/// Continuous LPV model of the tiltrotor's 20 mechanical error states.
struct LpvModel {
  Mat20 A0;                                ///< A at sigma = 0 (hover)
  std::vector<Mat20> A_sigma;              ///< A_i: secant slope over sigma_i's range, i = x, y, z
  Eigen::Matrix<double, kNx, kNu> B;       ///< at sigma = 0 (thesis: constant)
  Eigen::Matrix<double, kNx, kNd> D;
  Eigen::Vector3d sigma_min, sigma_max;    ///< box of the reference acceleration (the envelope)
  std::vector<Eigen::Vector3d> vertex_sigma;  ///< 8 corners
  double affinity_residual = 0.0;          ///< max ||A(sigma) - A_lpv(sigma)||_F / ||A0||_F over the grid
  double affinity_residual_relative = 0.0; ///< same, relative to max ||A(sigma) - A0||_F
  double sigma_part = 0.0;                 ///< max ||A_lpv(sigma) - A0||_F / ||A0||_F
  double b_variation = 0.0;                ///< max ||B(sigma) - B||_F / ||B||_F
  Mat20 at(const Eigen::Vector3d& sigma) const;
};

/// Discrete augmented error model with its normalization (n states, m inputs, nd
/// disturbance channels).
struct ErrorModel {
  double sample_time = 0.0;
  Discretization discretization = Discretization::Zoh;
  int measured = 0, n = 0, m = 0, nd = 0;
  std::vector<int> integrated;    ///< the measured states whose errors are integrated
  Equilibrium equilibrium;        ///< tiltrotor: the hover at the envelope's yaw
  LpvModel lpv;                   ///< tiltrotor only

  Eigen::MatrixXd A_c, B_c, D_c;  ///< continuous augmented model at sigma = 0
  Eigen::MatrixXd A, B, D;        ///< discrete nominal
  std::vector<Eigen::MatrixXd> A_vertices;  ///< discrete A at the 8 vertices (none: LTI)

  Eigen::VectorXd N_x;            ///< diagonal of N_x = 1 / state half-widths
  Eigen::VectorXd N_u;            ///< diagonal of N_u = 2 / (u_max - u_min)
  Eigen::MatrixXd A_n, B_n, D_n;  ///< normalized (D_n: normalized states per unit of d)
  std::vector<Eigen::MatrixXd> A_n_vertices;

  Eigen::VectorXd u_r_min, u_r_max;                  ///< range of the feedforward over the envelope
  Eigen::VectorXd input_error_min, input_error_max;  ///< u_min - max u_r, u_max - min u_r
};

/// Build the error model of the config's plant model over its envelope. Throws
/// ConfigError naming the section for an envelope without trims or a trajectory of
/// `envelope.trajectories` outside the configured box.
ErrorModel build_error_model(const Config& cfg);

/// The envelope of the config: the configured box, or (with `trajectories` and no box)
/// the range of those trajectories' accelerations and speeds widened by `margin`.
EnvelopeSettings resolve_envelope(const Config& cfg);

/// Augment a continuous (A, B, D) with the integrals of the errors of `integrated` (5.6).
void augment_with_integrals(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                            const std::vector<int>& integrated, Eigen::MatrixXd& Aa, Eigen::MatrixXd& Ba,
                            Eigen::MatrixXd& Da);

/// Discretize x' = A x + B u + D d with sample time T.
void discretize(const Eigen::MatrixXd& Ac, const Eigen::MatrixXd& Bc, const Eigen::MatrixXd& Dc, double T,
                Discretization method, Eigen::MatrixXd& A, Eigen::MatrixXd& B, Eigen::MatrixXd& D);

}  // namespace tmpc
