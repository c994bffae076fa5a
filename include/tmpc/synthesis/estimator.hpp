// State estimation for the offset-free tube law and the output-feedback tube
// (DESIGN.md 5b), in normalized coordinates.
//
// Kalman filter (steady state) on the error model augmented with the disturbance
// model of offset-free MPC (Pannocchia and Rawlings 2003; Muske and Badgwell 2002):
//   xi = (x, d, c),  xi+ = A_a xi + B_a u + w_a,  y = C xi + v
//   A_a = [A D E_c; 0 I 0; 0 0 I],  B_a = [B; 0; 0],  C = [S 0 0]
// x: the p physical (measured-kind) states of the error model, without the integral
// states (the controller's own: it integrates its estimate through the model's
// integral rows), d: the disturbance of the model (tiltrotor: the force on the load, N;
// D), c: constant accelerations on the angular-rate rows the disturbance does not
// explain (E_c: unit columns), S: the measured rows (every physical state, or positions,
// angles and angular rates).
// Filter form, each period: xi^- = A_a xi + B_a u (the applied input), then
//   xi = xi^- + L (y - C xi^-),  L = P C' (C P C' + R)^-1,
// P the stabilizing solution of the filter DARE (the LQR DARE of (A_a', C', Q, R)).
//
// Output-feedback tube (Mayne, Rakovic, Findeisen and Allgower, Automatica 42, 2006):
// with e = xi - xi_hat the estimation error and delta = x_hat - x_bar the control error,
//   e+     = (I - L C) A_a e + (I - L C) w_a - L v                       (estimation)
//   delta+ = (A + B K) delta + L_x (C A_a e + C w_a + v)                 (control)
// E is an RPI set of the first, Z_c of the second with its disturbance bounded by the
// interval hull of L_x C A_a E + L_x C W_a + L_x V (L_x: L's rows of x, zero on the
// integral rows, which follow the model), and the true state x = x_bar + delta + e_x
// lies in x_bar + Z_c + E_x: X_bar = X - (Z_c + E_x), U_bar = U - K Z_c. E_x has no
// extent on the integral states: their error is the sum of the position estimates'
// errors, zero-mean but not bounded by an invariant set (reported, not tightened).
// w_a: the state mismatch W, the force's change per step and the residual's change
// (a box); v: the noise box (noise_bound_sigmas standard deviations). Both sets are
// linear in the noise box: E = E_W + s E_V, Z_c = Z_W + s Z_V (Minkowski sums of RPI
// sets are RPI), so the largest noise scale s with non-empty tightened sets is exact
// for these outer approximations.
//
// Gaussian form of the noise part (chance constraints; Farina, Giulioni and Scattolini,
// J. Process Control 44, 2016; Hewing and Zeilinger, CDC 2018): a bounded box lets the
// worst case hold a constant bias for ever, which a filter of integrating disturbances
// reads as a force, so the bounded sets can be far larger than what white noise does.
// With v white and Gaussian, std V / z (z = noise_bound_sigmas), the joint error
// s = (e_v, delta_v) driven by v alone is linear and stationary:
//   s+ = [Se 0; L_x C A_a  A+BK] s + [-L; L_x] v,  Sigma_s = A_s Sigma_s A_s' + G diag(V^2) G'
// (a discrete Lyapunov equation, nominal loop; like the bounded form it takes the
// offset-free law's targets to cancel the estimated disturbance in the nominal
// prediction, x_hat+ = (A+BK) x_hat + L_x nu), and x - x_bar = delta + e_x has the
// per-row std sigma_x = sqrt(diag(T Sigma_s T')) / z (T = [I_x 0 | I]); u - u_bar = K delta.
// Tightening by z sigma_x and z sigma_u on top of the bounded sets of w_a (kept worst
// case) holds each constraint with the probability of z standard deviations of a normal
// (z = 3: 99.87 % one-sided) at every step in steady state; not a guarantee.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/sets/box.hpp"
#include "tmpc/sets/zonotope.hpp"

namespace tmpc {

struct KalmanDesign {
  int p = 0;                       ///< physical states in the filter
  std::vector<int> measured_rows;  ///< rows of x in y, in order
  Eigen::MatrixXd E_c;             ///< n x nc: the residual channels
  Eigen::MatrixXd A_a, B_a, C;     ///< augmented model and measurement map
  Eigen::MatrixXd Q, R;            ///< covariances designed for
  Eigen::MatrixXd P;               ///< a-priori error covariance (DARE)
  Eigen::MatrixXd L;               ///< filter gain, (n + nd + nc) x ny
  double spectral_radius = 0.0;    ///< of (I - L C) A_a (< 1: the filter converges)
};

/// The augmented model of (A, B, D, E_c) (p states) and rows; L, P, Q, R left empty.
KalmanDesign kalman_model(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                          const Eigen::MatrixXd& E_c, const std::vector<int>& measured_rows);

/// Steady-state gain for process covariance Q ((n + nd + nc) square) and measurement
/// covariance R (ny square). Throws std::runtime_error when the DARE has no
/// stabilizing solution (the augmented pair not detectable) or the filter diverges.
KalmanDesign design_kalman(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                           const Eigen::MatrixXd& E_c, const std::vector<int>& measured_rows,
                           const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

/// The same as design_kalman on the augmented model of `model` (from kalman_model() or a
/// design): its steady-state gain for Q and R (the noise-adaptive gains,
/// runtime/filter_gain_schedule.hpp). Throws as design_kalman.
KalmanDesign redesign_kalman(const KalmanDesign& model, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

/// The steady-state innovation's standard deviations, sqrt(diag(C P C' + R)) (ny; P the
/// a-priori covariance): the scale of the filter's innovation gate (tube_controller.hpp).
Eigen::VectorXd innovation_sd(const KalmanDesign& k);

/// The filter's start (a time-varying Kalman filter on the same model; Anderson and
/// Moore, Optimal Filtering, 1979, ch. 3): a filter engaged with the disturbances
/// unknown (a mass or trim error reads as a force) takes, from the a-priori covariance
/// P0, the gains of the Riccati recursion (Joseph form)
///   L_k = P_k C' (C P_k C' + R)^-1,  P_k+ = (I - L_k C) P_k (I - L_k C)' + L_k R L_k',
///   P_k+1 = A_a P_k+ A_a' + Q,
/// which converge to the steady gain L. The steady gain alone reads a force with the
/// filter's slowest pole (0.6 s for a 3.9 N mass imbalance), while the vertical speed
/// leaves its bound in 0.12 s. Returns L_0, L_1, ... up to the first within `tolerance`
/// of k.L (max-norm, relative to k.L's), at most max_steps; needs k.P, k.Q, k.R, k.L.
/// Throws std::runtime_error when a step's C P C' + R is not positive definite.
/// The defaults end the schedule within 0.1 % of L, after at most 2000 periods (24 s at 12 ms).
/// `innovation_sds`, when given, receives each step's innovation standard deviations
/// sqrt(diag(C P C' + R)) (the start's innovation gate, tube_controller.hpp).
std::vector<Eigen::MatrixXd> start_gains(const KalmanDesign& k, const Eigen::MatrixXd& P0, double tolerance = 1e-3,
                                         int max_steps = 2000, std::vector<Eigen::VectorXd>* innovation_sds = nullptr);

/// P0 of a filter engaged with the disturbances unknown and the state known to within
/// its measurement noise: block diagonal, the force's block force_std^2 I, the
/// residuals' residual_std^2 I, each measured state's variance (state_noise x its noise
/// standard deviation)^2 (R's diagonal), the unmeasured states' their steady variance.
/// A standard deviation or multiple of 0 keeps that block of the steady P (with its
/// correlations). The states' prior matters: the steady P's (a state known far better
/// than one measurement) makes the filter read the first samples' noise and the
/// vehicle's start as a force. nd forces in k's xi = (x, d, c).
Eigen::MatrixXd start_covariance(const KalmanDesign& k, Eigen::Index nd, double force_std, double residual_std,
                                 double state_noise);

/// P with the augmented states `states` made unknown: their rows and columns zeroed (no
/// correlation left) and std_dev^2 on their diagonal (a prior re-opened in part: the
/// vertical force of a step, tube_controller.hpp). Throws std::invalid_argument for a
/// state outside P or std_dev <= 0.
void open_states(Eigen::MatrixXd& P, const std::vector<Eigen::Index>& states, double std_dev);

/// The output-feedback tube's sets (see above), at noise scale 1 and their parts.
struct OutputFeedbackTube {
  Zonotope E_W, E_V;          ///< estimation error sets (augmented), of w_a and of v
  Eigen::VectorXd e_x_radius;  ///< interval-hull half-widths of E_x = (E_W + E_V) on x
  Zonotope Z_W, Z_V;          ///< control tube parts; Z_c = Z_W + Z_V
  Zonotope Z_c;
  Box x_bar, u_bar;            ///< X - (Z_c + E_x), U - K Z_c
  double noise_margin = 0.0;   ///< largest s with non-empty X - (Z_W + E_W,x + s (Z_V + E_V,x)) and U - K(...)
  int j_estimation = 0, j_control = 0;
  // Gaussian form (see above): z standard deviations of x - x_bar and u - u_bar from
  // the noise, and the sets tightened by them instead of by Z_V + E_V,x.
  Eigen::VectorXd x_sigmas_v, u_sigmas_v;  ///< z sigma_x (n), z sigma_u (m)
  Eigen::VectorXd e_x_sigmas_v;            ///< z sigma of the estimation error e_x alone (n)
  Eigen::VectorXd delta_sigmas_v;          ///< z sigma of the control error delta alone (n)
  Eigen::VectorXd e_x_radius_gaussian;     ///< E_W's half-widths on x + e_x_sigmas_v
  Box x_bar_gaussian, u_bar_gaussian;      ///< X - (Z_W + E_W,x + z sigma_x), U - (K Z_W + z sigma_u)
  double noise_margin_gaussian = 0.0;      ///< largest noise scale with those non-empty
};

/// Stationary covariance of s+ = A s + w, cov w = Q (A Schur stable): sum_k A^k Q A^k'
/// by doubling. Throws std::runtime_error when the sum does not converge.
Eigen::MatrixXd stationary_covariance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Q);

/// Vertices: the closed loops A_i + B K (nominal first, n >= p states, the first p
/// the filter's); W_a: box half-widths of w_a (p + nd + nc); V: noise box half-widths (ny). `lpv_robust` as the state tube's
/// variant (else the nominal loop only). Throws std::runtime_error when an RPI set
/// cannot be computed (an unstable loop).
OutputFeedbackTube output_feedback_tube(const KalmanDesign& k, const std::vector<Eigen::MatrixXd>& closed_loops,
                                        const Eigen::MatrixXd& K, const Eigen::VectorXd& W_a,
                                        const Eigen::VectorXd& V, const Box& X, const Box& U, double rpi_lambda);

}  // namespace tmpc
