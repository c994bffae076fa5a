// Tube feedback gain by Theorem 3.1 (LMIs solved as an SDP), W = L^-1, K = Y W^-1:
//   min kappa  s.t.  W > 0,  kappa I - W >= 0                                  (E5)
//   per LPV vertex A_i:
//     [W  (C W + D Y)'  (A_i W + B Y)'; C W + D Y  I  0; A_i W + B Y  0  W] > 0   (3.21)
//     thesis form (3.15), zeta free with [1 zeta'; zeta I] >= 0              (3.24):
//       [lambda W  0  (A_i W + B Y)'; 0  1-lambda  zeta'H_w'; A_i W + B Y  H_w zeta  W] >= 0
//     robust form (E4): zeta replaced by the whole of W (||zeta||_2 <= sqrt(r)):
//       [lambda W  0  (.)'; 0  ((1-lambda)/r) I_r  H_w'; A_i W + B Y  H_w  W] >= 0
//   per input channel j: [u_max_j^2  Y_j; Y_j'  W] >= 0                        (3.19)
// with C'C = Sigma_rho, D'D = Sigma_lambda, C'D = 0. Every solution is checked
// independently: LMI eigenvalues, spectral radius of A_i + B K, the input bound on
// the ellipsoid {x'W^-1 x <= 1}.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/synthesis/lmi.hpp"

namespace tmpc {

enum class LmiForm { Thesis, Robust };
const char* to_string(LmiForm f);

struct LmiGainProblem {
  std::vector<Eigen::MatrixXd> A;  ///< vertices (the nominal model may be one of them)
  Eigen::MatrixXd B;
  Eigen::MatrixXd Q;               ///< Sigma_rho
  Eigen::MatrixXd R;               ///< Sigma_lambda
  Eigen::MatrixXd Hw;              ///< generators of W (n x r)
  Eigen::VectorXd u_max;           ///< symmetric input bounds of the feedback
  LmiForm form = LmiForm::Thesis;
  double lambda = 0.99;            ///< contraction rate of (3.11)
  double margin = 1e-7;            ///< strictness of the "> 0" inequalities
  double w_floor = 1e-4;           ///< W >= w_floor I: keeps min kappa bounded (see lmi_gain.cpp)
};

struct LmiGainResult {
  bool feasible = false;           ///< solver succeeded and the independent checks pass
  SdpStatus status = SdpStatus::NumericalFailure;
  std::string message;             ///< solver verdict, or the failed check
  Eigen::MatrixXd K, W, L;         ///< L = W^-1 (Lyapunov matrix, terminal cost option)
  Eigen::VectorXd zeta;            ///< thesis form only
  double kappa = 0.0;
  double lambda = 0.0;
  std::vector<double> vertex_spectral_radius;
  std::vector<double> block_min_eigenvalue;  ///< per LMI block at the solution
  std::vector<std::string> block_names;
  double worst_block_eigenvalue = 0.0;
  double input_bound_ratio = 0.0;  ///< max_j sqrt(K_j W K_j') / u_max_j (<= 1 required)
  double seconds = 0.0;
  int variables = 0;
};

/// Solve Theorem 3.1 for a fixed lambda.
LmiGainResult solve_lmi_gain(const LmiGainProblem& p);

/// Line search over lambda in (0, 1): the smallest feasible lambda on a grid
/// refined by bisection (`steps` solves at most).
LmiGainResult solve_lmi_gain_line_search(LmiGainProblem p, int steps = 6);

}  // namespace tmpc
