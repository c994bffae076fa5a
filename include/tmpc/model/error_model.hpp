// Linear error model along the helix, thesis section 5.2:
//   x_tilde' = A(sigma) x_tilde + B u_tilde + D d                            (5.5)
//   sigma = xi_r'' (3 parameters). With the thesis-literal reference attitude u_r is
//   affine in sigma, hence so is A (at q_r' = 0); with the trim attitude (default)
//   it nearly is. A(sigma) = A_0 + sum_i sigma_i A_i with A_0 at sigma = 0 and A_i
//   the secant of A over sigma_i's range; vertices at the 8 corners of sigma's box
//   augmented with the integrals of the x, y, z, psi errors:                 (5.6)-(5.7)
//   A_a = [A 0; C 0], B_a = [B; 0], D_a = [D; 0]
//   discrete: exact ZOH (default) or Euler A_z = I + A_a T (thesis (5.8), E1)
//   normalized: x_n = N_x x, u_n = N_u u, A_n = N_x A_z N_x^-1,
//               B_n = N_x B_z N_u^-1                                           (5.10)-(5.11)
// The model says how affine A really is: the true A(t) along the helix (with the
// reference velocity) against A_0 + sum sigma_i(t) A_i.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/equilibrium.hpp"

namespace tmpc {

constexpr int kNa = 24;  ///< augmented error states

using Mat20 = Eigen::Matrix<double, kNx, kNx>;
using Mat24 = Eigen::Matrix<double, kNa, kNa>;
using Vec24 = Eigen::Matrix<double, kNa, 1>;
using Mat24x4 = Eigen::Matrix<double, kNa, kNu>;
using Mat24x3 = Eigen::Matrix<double, kNa, kNd>;

/// Continuous LPV model of the 20 mechanical error states.
struct LpvModel {
  Mat20 A0;                                ///< A at sigma = 0 (hover)
  std::vector<Mat20> A_sigma;              ///< A_i: secant slope over sigma_i's range, i = x, y, z
  Eigen::Matrix<double, kNx, kNu> B;       ///< at sigma = 0 (thesis: constant)
  Eigen::Matrix<double, kNx, kNd> D;
  Eigen::Vector3d sigma_min, sigma_max;    ///< box of the reference acceleration
  std::vector<Eigen::Vector3d> vertex_sigma;  ///< 8 corners
  double affinity_residual = 0.0;          ///< max_t ||A(t) - A_lpv(sigma(t))||_F / ||A0||_F
  double affinity_residual_relative = 0.0; ///< same, relative to max_t ||A(t) - A0||_F
  double sigma_part = 0.0;                 ///< max_t ||A_lpv(sigma(t)) - A0||_F / ||A0||_F
  double b_variation = 0.0;                ///< max_t ||B(t) - B||_F / ||B||_F (0 for the literal attitude)
  Mat20 at(const Eigen::Vector3d& sigma) const;
};

/// Discrete augmented error model with its normalization.
struct ErrorModel {
  double sample_time = 0.0;
  Discretization discretization = Discretization::Zoh;
  Equilibrium equilibrium;
  LpvModel lpv;

  Mat24 A_c;                      ///< continuous augmented A_a at sigma = 0
  Mat24x4 B_c;
  Mat24x3 D_c;
  Mat24 A;                        ///< discrete nominal A_z (sigma = 0)
  std::vector<Mat24> A_vertices;  ///< discrete A_z at the 8 vertices
  Mat24x4 B;                      ///< discrete B_z
  Mat24x3 D;                      ///< discrete D_z

  Vec24 N_x;                      ///< diagonal of N_x = 1 / state half-widths
  Eigen::Vector4d N_u;            ///< diagonal of N_u = 2 / (u_max - u_min)
  Mat24 A_n;                      ///< normalized nominal
  std::vector<Mat24> A_n_vertices;
  Mat24x4 B_n;
  Mat24x3 D_n;                    ///< normalized states per newton: N_x D_z

  Eigen::Vector4d u_r_min, u_r_max;            ///< range of u_r along the mission
  Eigen::Vector4d input_error_min, input_error_max;  ///< u_min - min u_r, u_max - max u_r
};

/// Linearize along the helix of `cfg`, build the LPV form, augment, discretize and normalize.
ErrorModel build_error_model(const Config& cfg, const TiltrotorModel& model);

/// Augment a 20-state continuous (A, B, D) with the integrals of x, y, z, psi (5.6).
void augment_with_integrals(const Mat20& A, const Eigen::Matrix<double, kNx, kNu>& B,
                            const Eigen::Matrix<double, kNx, kNd>& D, Mat24& Aa, Mat24x4& Ba, Mat24x3& Da);

/// Discretize x' = A x + B u + D d with sample time T.
void discretize(const Mat24& Ac, const Mat24x4& Bc, const Mat24x3& Dc, double T, Discretization method, Mat24& A,
                Mat24x4& B, Mat24x3& D);

}  // namespace tmpc
