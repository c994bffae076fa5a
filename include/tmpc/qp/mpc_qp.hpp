// Nominal MPC problem data, thesis (3.50)-(3.55), in normalized coordinates:
//   x_hat = P u_hat + Q x0,  x_hat = (x(1), ..., x(N)),  u_hat = (u(0), ..., u(M-1))  (3.53)
//   P with move blocking: u(i) = u(M-1) for i >= M (the eps(k, j) column sums of (3.53))
//   V = x_hat' W_x x_hat + u_hat' W_u u_hat                                            (3.54)
//   W_x = blkdiag(Sigma_rho, ..., Sigma_rho, L),
//   W_u = blkdiag(Sigma_lambda, ..., Sigma_lambda, (N - M + 1) Sigma_lambda)
//     (the last input is applied N - M + 1 times in (3.50); (3.54) omits the factor)
//   u(i) in U_bar (i < M), x(i) in X_bar (i = 1..N)                                   (3.55)
// Condensed form for solvers: min 1/2 z'H z + (F x0)'z  s.t.  l(x0) <= A z <= u(x0),
//   H = 2 (P'W_x P + W_u), F = 2 P'W_x Q, A = [I; P], bounds [U_bar; X_bar - Q x0].
// Offset-free form (disturbance_target.hpp): the nominal model is affine,
// x+ = A x + B u + D d + c (d: the estimated force, c: the filtered remaining model
// residual), the parameter is (x0 - x_s, d, c) with x_s = Tx d, u_s = Tu d, and the QP
// is the same one in coordinates around the steady state of d:
//   x_hat - X_s = P (u_hat - U_s) + Q (x0 - x_s) + Phi c,  Phi = [I; I + A; ...; sum A^i],
//   bounds [U_bar - U_s; X_bar - X_s - Q (x0 - x_s) - Phi c], F's c block 2 P'W_x Phi.
// Softened form (soft_penalty > 0, parametric_qp.hpp): the state constraints with an
// exact L1 penalty on one slack per state, shared by the horizon; inputs stay hard.
// Input-rate weight (add_input_rate_weight; not in the thesis, issue 19): V gains
//   sum_{i=0}^{M-1} (u(i) - u(i-1))' Sigma_delta (u(i) - u(i-1)),  u(-1) = v_prev,
// the previous period's nominal input (a parameter, after x0 [, d, c]; in the
// offset-free form v_prev - u_s, as u_hat is): H += 2 Delta'(I (x) Sigma_delta) Delta
// (Delta: first differences of the M blocks), F's v_prev block -2 Sigma_delta on u(0).
// Move blocking holds u(i) = u(M-1) for i >= M: no later differences.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/sets/box.hpp"

namespace tmpc {

/// A polyhedral domain of a QP's parameter: {theta : lo <= D theta <= hi}.
struct ParameterDomain {
  Eigen::MatrixXd D;       ///< rows over theta
  Eigen::VectorXd lo, hi;  ///< bounds of D theta (+-infinity allowed)
  bool empty() const { return D.rows() == 0; }
  /// theta in the domain, each row within tol (absolute); false for a wrong size.
  bool contains(const Eigen::VectorXd& theta, double tol = 0.0) const;
};

struct MpcQpData {
  int n = 0, m = 0, N = 0, M = 0;
  Eigen::MatrixXd A, B;            ///< nominal model (normalized)
  Eigen::MatrixXd Sigma_rho, Sigma_lambda, L;  ///< stage and terminal weights (normalized)
  Box x_bar, u_bar;                ///< tightened sets (normalized)
  Eigen::MatrixXd P, Q;            ///< prediction matrices (3.53)
  Eigen::MatrixXd H, F;            ///< condensed Hessian and linear-term map
  Eigen::MatrixXd Tx, Tu;          ///< offset-free targets x_s = Tx d, u_s = Tu d (nd = 0: none)
  Eigen::MatrixXd Phi;             ///< offset-free: response of x_hat to the constant c (N n x n)
  /// Softened state constraints: rho of the exact L1 penalty rho 1's on the slacks
  /// (0: hard constraints). Exact (no slack while the hard QP is feasible) when rho
  /// exceeds every state's sum of multipliers over the horizon (design.hpp computes it).
  double soft_penalty = 0.0;
  bool soft() const { return soft_penalty > 0.0; }
  /// Input-rate weight (m x m, normalized; empty: none), see above.
  Eigen::MatrixXd Sigma_delta;
  bool rate_weighted() const { return Sigma_delta.size() > 0; }
  /// Rows of the hard QP (ParametricQp::from_mpc's numbering) certified by LPs never to
  /// bind while the parameter is in `domain` (redundant_rows.hpp; the artifact records
  /// them): the active-set solver leaves them out there. Empty: none known.
  std::vector<int> redundant_rows;
  ParameterDomain domain;
  int variables() const { return M * m; }
  int disturbances() const { return static_cast<int>(Tx.cols()); }
  bool offset_free() const { return disturbances() > 0; }
  /// x0, then (offset-free) d and c, then (rate-weighted) v_prev.
  int parameters() const { return n + (offset_free() ? disturbances() + n : 0) + (rate_weighted() ? m : 0); }
  /// Index of v_prev in the parameter (rate-weighted form).
  int rate_parameter() const { return n + (offset_free() ? disturbances() + n : 0); }
  int state_constraints() const { return N * n; }
  Eigen::MatrixXd Wx() const;      ///< dense W_x
  Eigen::MatrixXd Wu() const;      ///< dense W_u
};

/// Offset-free form: targets (Tx, Tu) of the disturbance and Phi. Throws on sizes.
void make_offset_free(MpcQpData& d, const Eigen::MatrixXd& Tx, const Eigen::MatrixXd& Tu);

/// Input-rate weight Sigma_delta (m x m, symmetric positive semidefinite; a zero matrix
/// removes it): H gains 2 Delta'(I (x) Sigma_delta) Delta (above). Throws on sizes, an
/// asymmetric or indefinite weight, or a second call.
void add_input_rate_weight(MpcQpData& d, const Eigen::MatrixXd& Sigma_delta);

/// Build P, Q, W_x, W_u and the condensed H, F. Throws on inconsistent sizes.
MpcQpData build_mpc_qp(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Sigma_rho,
                       const Eigen::MatrixXd& Sigma_lambda, const Eigen::MatrixXd& L, const Box& x_bar,
                       const Box& u_bar, int N, int M);

/// One QP instance: min 1/2 z'Hz + f'z  s.t.  lo <= A z <= hi.
struct CondensedQp {
  Eigen::MatrixXd H;
  Eigen::VectorXd f;
  Eigen::MatrixXd A;
  Eigen::VectorXd lo, hi;
  double constant = 0.0;  ///< x0' Q' W_x Q x0: the cost V = 1/2 z'Hz + f'z + constant
};

/// The hard nominal QP at x0 (rate-weighted: with v_prev = 0, the steady input).
CondensedQp condensed_qp(const MpcQpData& d, const Eigen::VectorXd& x0);

/// The full cost V(u_hat) of (3.54) at x0, evaluated directly from P, Q, W_x, W_u, plus
/// the input-rate term with v_prev (empty: 0) when rate-weighted.
double mpc_cost(const MpcQpData& d, const Eigen::VectorXd& x0, const Eigen::VectorXd& u_hat,
                const Eigen::VectorXd& v_prev = Eigen::VectorXd());

}  // namespace tmpc
