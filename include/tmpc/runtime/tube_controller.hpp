// The tube control law, thesis (5.9), in normalized coordinates:
//   u = u_r + N_u^-1 (u_bar(0) + K (x_tilde_n - x_bar_n))
// with the nominal state propagated by the nominal model (Mayne's tube MPC):
//   x_bar+ = A x_bar + B u_bar(0)
// (optionally re-initialised to the measured error when that lies in X_bar), the
// applied input clipped to the actuator limits (counted), and the LQR fallback
// u = u_r + N_u^-1 K_lqr x_tilde_n used when the optimizer fails or is late (past
// revert_beyond times the box, the tube gain's u_r + N_u^-1 K x_tilde_n: below).
// Offset-free option (DESIGN.md section 4), an observer on the one-step residual
// r = x_n - A x_n,prev - B u_n,prev (normalized, applied input):
//   d_hat+ = d_hat + beta ((S D)^-1 S r - d_hat)   the disturbance (tiltrotor: the force
//                                                   on the load, N); S: the rows of the
//                                                   measured states of kind velocity
//   c_hat+ = c_hat + beta (r - D d_hat+ - c_hat)     the rest of the model mismatch
// The nominal model becomes affine, x_bar+ = A x_bar + B u_bar(0) + D d_hat + c_hat, and
// the QP (built from artifact.qp(true), mpc_qp.hpp) predicts with it around the
// steady state (x_s, u_s) = (Tx, Tu) d_hat, with its sets shifted; u_bar(0) includes
// u_s and the fallback is u_s + K_lqr (x_n - x_s). The tube error x_tilde - x_bar then
// sees only the change of the mismatch, not its constant part.
// With the artifact's Kalman filter (estimator "kalman", synthesis/estimator.hpp) the
// observer is the filter instead: each period xi^- = A_a xi + B_a u_prev, then
// xi = xi^- + L (y - C xi^-) on the measured rows; the estimate x_hat replaces the
// measurement everywhere in the law (tube error, fallback, state box), d_hat is its
// disturbance part and c_hat = E_c times its residual part. The filter estimates the
// measured (physical) states; the integral states are the model's integral rows
// applied to the previous estimate. A state that does not follow the previous one by
// one period restarts the filter's state part and the integrals from it. After reset()
// the filter's gain is time-varying, L_k from the artifact's start prior (the force
// unknown; estimator.hpp start_gains(), computed at construction), until it reaches L.
// The switched observer ("switched": the artifact's filter and its noise monitor,
// noise_monitor.hpp) runs both every period, each with its own disturbance estimate,
// and flies the filter's while the monitor reads noise, the residual observer's while
// it reads clean sensors (the filter at the start; if the monitor's first check, 72 ms,
// reads clean sensors, the residual observer takes over at once and the nominal state
// restarts at the measurement, as reset() does without the filter). Later switches are
// bumpless: the flown
// state and disturbance estimates are w (filter's) + (1 - w) (residual observer's),
// the weight w ramped to its target in kBlendToFilter_s (towards the filter) or
// kBlendToResidual_s; an abrupt switch jumped the steady-state input by the estimates'
// difference (a sensor bias reads differently in the two) and kicked a servo rate past
// its bound. The nominal state is not reset; while the residual observer flies alone,
// the filter's integral states follow the measured ones. The monitor skips a period
// whose residual carries an input of the softened QP or the LQR fallback (the last
// period's): the law is then past what the hard constraints hold, where the linear
// model's mismatch is large and the inputs jump, and that reads like noise (a 3.5 N
// force's thrusts chattering at their 30 N bound read 4 times the design's noise and
// brought the filter in, whose slower force estimate swung the vertical speed; 0.046
// for 3 N). Noise that starts there is read once the hard law flies again.
// The filter's steady gain follows the monitor's noise level (filter_gain_schedule.hpp,
// adaptive_filter_gain); the filter alone ("kalman") runs a monitor for that only.
// Measurement glitches (innovation gating, as in navigation filters; Bar-Shalom, Li and
// Kirubarajan 2001, 5.4): a measured position or angle whose innovation
// y_i - (A_a xi + B_a u)_i exceeds kInnovationGate_sigmas of its standard deviation
// sqrt(C P C' + R)_ii (the start schedule's P of that step, then the steady P of the
// gain flown; velocities and rates are not gated: a force step shows there first, and
// a 3 N step's innovations passed 8 sigmas of them) is replaced by the filter's
// prediction this period, for every observer, the monitor and the law (a glitch read by
// the residual observer went straight to the servos), when it got there in one period:
// its innovation moved by more than the gate since the last period (a real transient
// that the filter lags builds its innovation up over periods: a rotor's 15 % thrust
// loss crossed the gate after 0.24 s, and replacing it then kicked the servo rates to
// 1.6 times their bound); at most kGateRun periods in a row, after which the row is
// taken until its innovation is back inside (a real jump must not lock the filter out). Not after a period of the softened QP or the LQR
// fallback, as the monitor: there the linear model's prediction is far off (a 4 N
// force's fallback flight lost the vehicle to the replaced measurements).
// Disturbance steps (step_detection; maneuver detection of tracking filters, Bar-Shalom,
// Li and Kirubarajan 2001, 11.2): the steady gain, tuned against the noise, reads a
// new disturbance over about a second (a 15 % thrust loss with noisy sensors: 142
// violations). Each measured row's innovation over its deviation is summed with a
// fading memory, s_i <- kStepMemory s_i + nu_i / sd_i (white innovations: |s_i|
// stays near 1.4 of a deviation); |s_i| > kStepThreshold, confirmed by the next
// innovation (beyond kStepConfirm deviations, the same sign: a lone outlier decays in
// the sum), is a step, once per row until its sum is back below half the threshold.
// The filter then runs, from its current estimate, the gains of a prior with the
// angular-acceleration residuals unknown (start_gains from start_covariance, the
// residuals' deviation kReopenResidualStd) into its steady gain; the force's block
// keeps its steady covariance (re-opened whole, a horizontal force's estimate moves
// the target's rod tilt at once, and the sustained 3 N's transient grew).
// step_reopens_lift (on by default): the force components whose steady state (the
// offset-free target x_s = Tx d) moves no state by more than kReopenTargetShift of its
// bound for a force of kReopenForceStd are re-opened too, to that deviation (the
// tiltrotor: the vertical force, which the vehicle holds by thrust alone). The state
// block's reset drops its correlations with the force, so with the force kept a rotor's
// lost lift was read slower than by the steady gain; re-opened, in a fraction of the
// time (the 80-flight sweep: the vertical speed past its bound in one fault flight
// instead of nine). A large horizontal force's swing has a vertical transient that a
// re-opened lift reads as lift (a sustained 4 N on the load was then lost; README
// "Re-opening the lift"), so the step is classified first: a generalized likelihood
// ratio over its innovation signature (step_signature.hpp; the kStepWindow newest
// innovations, whitened) tests "a step in the re-opened forces and the residuals"
// against "a step in every force and the residuals"; the lift is re-opened only when
// the second does not explain the window significantly better (the GLRs' difference
// within the chi-square quantile at kLiftConfidence for the forces left out).
// step_corrects_input (on by default, with step_reopens_lift): the actuators' class
// too. A step mu_j in input j is the step v_j mu_j of the filter's disturbance states
// whose effect [D E_c] v_j matches B's column j (least squares, kept where within
// kInputMatch; Pannocchia and Rawlings 2003's input-disturbance model). Where the GLR of
// a step in every input's direction is at least kInputExplained of every force's and
// residual's (a share: the plant's nonlinearity leaves a misfit that grows with the
// step), the prediction takes the step's effect since its fitted onset m, Phi^m E mu
// (step_signature.hpp's jump; Willsky and Jones' estimate correction), mu read along
// the directions the window determines to within kInputDetermined of a prior of
// kInputStepStd of each input's largest limit (a rotor's differential thrust, not yet
// its lift, which the re-opened lift reads), and not for an input whose compensation
// would move a state by more than kInputKick of its bound in one period (a servo's
// torque moves its rate at once: compensated at once, it kicked the rate the other way).
// late_step_keeps_gain (on by default, with step_reopens_lift): a step whose GLR onset
// (every force's class) is the window's oldest period began before the window; the
// steady gain has been reading it for kStepWindow periods or more, and it keeps that
// gain (no re-opening, no correction). Re-opened that late, the gains kicked the servo
// rates: a servo's torque bias detected 0.29 s after its onset, its rate back near zero,
// swung to 1.47 times its bound once re-opened (README "A step older than the window").
// Not while the start's schedule runs or within kStepHold periods of a step, not after
// a softened or fallback period, and only where the noise monitor reads the noise the
// gain flown is designed for (up to kStepNoiseLevel times it): the re-opened prior's
// gains and deviations are computed per noise scale of the gain schedule
// (filter_gain_schedule.hpp), up to kStepScaleMax times the design's noise.
// No allocation in step(); it never throws.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/runtime/filter_gain_schedule.hpp"
#include "tmpc/runtime/noise_monitor.hpp"
#include "tmpc/runtime/step_signature.hpp"
#include "tmpc/solvers/solver.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/start_schedule.hpp"

namespace tmpc {

struct TubeControllerOptions {
  bool reinitialize_nominal = false;  ///< x_bar := x_tilde when x_tilde is in X_bar
  bool offset_free = false;           ///< disturbance observer + targets; the solver must be
                                      ///< built from artifact.qp(true)
  double observer_gain = 0.05;        ///< beta in (0, 1]: time constant T / beta (0.24 s)
  std::string observer = "residual";  ///< offset-free: "residual", "kalman" (the artifact's filter) or
                                      ///< "switched" (both, chosen by the artifact's noise monitor)
  /// kalman or switched: the filter's gain follows the noise monitor's level
  /// (filter_gain_schedule.hpp; the filter alone runs a monitor for the level only);
  /// false: the design's gain at every level.
  bool adaptive_filter_gain = true;
  /// kalman or switched: the filter's innovation gate replaces glitched position and angle
  /// measurements by its prediction (below); false: every measurement is taken.
  bool innovation_gate = true;
  /// kalman or switched: a step in the disturbances (a rotor's thrust loss), detected in
  /// the filter's innovations, re-opens the filter's disturbance covariance (below);
  /// false: the steady gain reads a step at its own pace.
  bool step_detection = true;
  /// step_detection: a step not classified as a horizontal force re-opens the vertical
  /// force on the load too (below), which reads a rotor's lost lift at once; false: the
  /// force's block keeps its steady covariance.
  bool step_reopens_lift = true;
  /// step_reopens_lift: a step that one actuator's input explains (an actuator's fault:
  /// a thrust lost, a servo's torque biased) corrects the filter's prediction by that
  /// step's effect since its onset (below); false: the re-opened gains alone read it.
  bool step_corrects_input = true;
  /// step_reopens_lift: a step detected after it has left the detection window (its
  /// onset older than the window) keeps the steady gain, which has been reading it
  /// (below); false: every step detected re-opens the gains.
  bool late_step_keeps_gain = true;
  /// Reversion past the linear model's region (a supervisor; off at 0): once a state of
  /// the error (the estimate flown) is past revert_beyond times its bound in X, the tube
  /// gain's unconstrained law u = u_s + K (x_n - x_s) flies every period, counted as a
  /// fallback, until each state is back within revert_within times its bound; then the
  /// MPC law again from the nominal state x_bar = x_n (hysteresis). Past the box the
  /// softened QP spends the servos on the immediate violation and lost a sustained 4 N
  /// force that the unconstrained law rides out; the tube gain, not K_lqr, because with
  /// raw noisy measurements the K_lqr torques chattered the vehicle down in 26 periods
  /// (README "Reverting past the model's region"). revert_beyond 0 or > 1, revert_within
  /// in [1, revert_beyond].
  double revert_beyond = 0.0;
  double revert_within = 1.5;
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

/// The artifact's tube law (its design config's `tube_law` and `estimation`),
/// overridden by `law` when not empty: "mayne" or "offset-free"; `observer_gain` > 0
/// overrides the gain; `observer` ("residual", "kalman" or "switched") the observer.
/// Throws std::invalid_argument for another name, "kalman" without the artifact's
/// filter or "switched" without its noise monitor.
TubeControllerOptions tube_law_options(const ControllerArtifact& a, const std::string& law = "",
                                       double observer_gain = 0.0, const std::string& observer = "");

/// What one period decided.
struct ControlStep {
  Eigen::VectorXd u;                                ///< applied input (physical, clipped)
  Eigen::VectorXd u_bar;                            ///< nominal input u_bar(0), physical error units
  Eigen::VectorXd x_bar;                            ///< nominal state used (normalized)
  Eigen::VectorXd x_tilde;  ///< the state estimate flown (normalized): the filter's, the measurement or a blend
  SolveStatus status = SolveStatus::Converged;
  int iterations = 0;
  double solve_us = 0.0;
  bool fallback = false;  ///< the LQR law was applied
  bool reverted = false;  ///< a fallback of the reversion: the tube gain's law, the error past revert_beyond
  bool clipped = false;   ///< an input hit an actuator limit
  bool in_tube = true;    ///< x_tilde - x_bar inside the interval hull of Z
  double tube_ratio = 0.0;  ///< max_i |x_tilde - x_bar - c_Z|_i / radius_i (<= 1: inside)
  int tube_worst = 0;       ///< the state i of that maximum
  bool in_state_box = true;  ///< x_tilde inside X
  Eigen::VectorXd d_hat;                            ///< estimated disturbance (tiltrotor: force on the load, N)
  bool softened = false;     ///< the hard QP was infeasible: the softened QP's input (controller_solver.hpp)
  double slack_max = 0.0;    ///< its largest slack, physical units of state slack_state
  int slack_state = -1;
  bool filtered = false;     ///< the Kalman filter's estimate flies (switched observer: the monitor's choice)
  double filter_weight = 0.0;  ///< the filter's share of the flown estimate (0: the measurement; kalman: 1)
  double noise_level = 0.0;  ///< the noise monitor's level (fraction of the design's; 0 without one)
  int gated_rows = 0;  ///< measured rows the filter's innovation gate replaced by its prediction this period
  bool step_detected = false;  ///< step_detection: a disturbance step was detected; the filter's gains re-opened
  bool step_reopened_lift = false;  ///< that step re-opened the lift too (step_reopens_lift, classified as not horizontal)
  double step_horizontal_glr = 0.0;  ///< that step's GLR difference, every force against the lift's (step_reopens_lift)
  bool step_input = false;  ///< step_corrects_input: that step was read as the actuators' and corrected
  bool step_late = false;  ///< late_step_keeps_gain: a step was detected older than the detection window and
                           ///< left to the steady gain (step_detected false)
  double filter_noise_scale = 1.0;  ///< the noise (times the design's) the filter's steady gain is chosen for
                                    ///< (during the filter's start schedule, the one it will fly after)
};

/// The telemetry's step code of one period: 0 none, 1 a step re-opened the filter's
/// gains, 2 the lift's too, 3 a step older than the detection window, left to the
/// steady gain (step_late).
inline int step_code(const ControlStep& s) {
  return s.step_detected ? (s.step_reopened_lift ? 2 : 1) : s.step_late ? 3 : 0;
}

class TubeController {
 public:
  /// `solver` may be null when the optimizer runs elsewhere (AsyncOptimizer): then use
  /// prepare() and finish() instead of step().
  TubeController(const ControllerArtifact& a, std::unique_ptr<QpSolver> solver, TubeControllerOptions opt = {});

  /// One period: x_tilde (physical, n error states), u_r the feedforward, and whether
  /// the optimizer's answer arrived in time (false: the fallback is applied).
  /// Equals prepare(), a solve from the returned nominal state, finish().
  const ControlStep& step(const Eigen::VectorXd& x_tilde, const Eigen::VectorXd& u_r, bool optimizer_in_time = true);
  /// First half of a period: the parameter the optimizer solves for, the nominal
  /// state (normalized), or (x_bar - x_s, d_hat) offset-free. `consecutive`: x_tilde
  /// follows the previous prepare()'s state by one period, with finish()'s input
  /// applied in between (false after a stale state or a safe command: the observer
  /// skips that residual).
  const Eigen::VectorXd& prepare(const Eigen::VectorXd& x_tilde, bool consecutive = true);
  /// Second half: the law (5.9) with the optimizer's result, or the LQR fallback when
  /// `r` is null (late, busy), not converged, or not `in_time` (its status is still
  /// recorded). Call prepare() first in the same period.
  const ControlStep& finish(const Eigen::VectorXd& u_r, const SolveResult* r, bool in_time = true);
  /// Start the nominal state at a (physical) error state, e.g. at mission start.
  void reset(const Eigen::VectorXd& x_tilde);

  const ControllerArtifact& artifact() const { return a_; }
  /// Entries of the optimizer's parameter: n, plus nd + n offset-free.
  int parameters() const { return static_cast<int>(theta_.size()); }
  long clipped_count() const { return clipped_; }
  long fallback_count() const { return fallbacks_; }
  long reverted_count() const { return reverted_periods_; }
  /// The force components (columns of the artifact's D) a step re-opens (above); empty
  /// without step detection or step_reopens_lift.
  const std::vector<Eigen::Index>& step_reopened_forces() const { return reopened_forces_; }

 private:
  /// The schedule whose prior is open: the re-opened one, else the start (empty: none).
  const StartSchedule& opening() const;
  /// The filter's innovation deviations this period: the start's or the re-opened
  /// prior's schedule, then the steady gain's.
  const Eigen::VectorXd& innovation_sd_now() const;
  /// Step detection (above) on this period's innovations.
  void detect_step();

  const ControllerArtifact& a_;
  std::unique_ptr<QpSolver> solver_;
  TubeControllerOptions opt_;
  Eigen::VectorXd x_bar_, x_n_, e_, dev_, z_half_, next_;
  // Offset-free observer and targets.
  Eigen::MatrixXd Tx_, Tu_, D_pinv_;
  Eigen::VectorXd theta_, x_s_, x_prev_, resid_;
  Eigen::VectorXd u_s_, u_prev_n_, u_n_, ub_, u_raw_;
  Eigen::VectorXd v_prev_;  ///< the previous nominal input (normalized): the rate weight's u(-1)
  Eigen::VectorXd d_hat_, d_raw_;
  Eigen::VectorXd c_hat_;
  Eigen::VectorXd y_;               ///< this period's measurement (normalized)
  Eigen::VectorXd d_res_, c_res_;   ///< the residual observer's estimates
  Eigen::VectorXd d_kf_, c_kf_;     ///< the filter's
  bool residual_ = false;  ///< the residual observer runs (observer residual or switched)
  std::unique_ptr<NoiseMonitor> monitor_;  ///< switched observer; the filter alone with adaptive_filter_gain (the level only)
  double w_ = 1.0;                         ///< the filter's weight in the flown estimate
  static constexpr double kBlendToFilter_s = 0.1, kBlendToResidual_s = 0.5;
  static constexpr double kPriorGate_sigmas = 5.0;  ///< the first measurement refutes the filter's prior beyond this
  static constexpr double kInnovationGate_sigmas = 20.0;  ///< a glitch: an innovation beyond this
  static constexpr int kGateRun = 3;  ///< periods a row may be replaced in a row (then it is a jump, taken)
  bool have_prev_ = false;
  bool prev_off_law_ = false;  ///< last period's input: the softened QP's or the LQR fallback's (monitor skips)
  // Kalman filter (estimator "kalman").
  bool kalman_ = false;  ///< the filter runs (observer kalman or switched)
  bool rate_ = false;  ///< the artifact's QP has an input-rate weight: theta ends with v_prev - u_s
  bool from_prior_ = false;  // the Kalman filter starts from its prior at the next prepare()
  std::vector<char> prior_refuted_;  ///< per state: the first measurement refuted the prior (nominal starts there)
  Eigen::MatrixXd A_a_, B_a_, L_kf_, E_c_;
  // The filter's start (artifact.estimator_start): the time-varying gains of its first
  // periods after reset(), then L_kf_; kf_step_ counts the filter's updates since.
  std::shared_ptr<const StartSchedule> start_;  ///< the start's gains and deviations (null: none)
  std::unique_ptr<FilterGainSchedule> schedule_;  ///< switched observer, adaptive_filter_gain
  std::size_t kf_step_ = 0;
  std::vector<int> rows_;
  Eigen::VectorXd xi_, xi_pred_, innov_, x_hat_;
  // The innovation gate (above): the design gain's innovation deviations (the schedule
  // keeps its own), and per measured row the periods replaced in a row.
  Eigen::VectorXd innov_sd_;
  std::vector<std::size_t> gated_rows_;  ///< indices into rows_ of the positions and angles
  std::vector<int> gate_run_;
  // Step detection (above): the gains of the re-opened prior and their innovation
  // deviations, which schedule kf_step_ counts in, and the fading sums.
  std::vector<std::shared_ptr<const StartSchedule>> reopen_;  ///< per noise scale of the gain schedule, the design's first
  std::size_t reopen_at_ = 0;      ///< the one running (reopened_)
  bool reopened_ = false;
  Eigen::VectorXd step_sum_;
  std::vector<char> step_armed_;    ///< per row: may detect (re-armed once its sum is back below half the threshold)
  std::vector<char> step_pending_;  ///< per row: its sum passed the threshold last period
  std::vector<Eigen::Index> reopened_forces_;  ///< force components a step re-opens
  // step_reopens_lift: the lift's re-opened priors (reopen_ keeps the force), the step
  // signatures per noise scale (every force with the residuals; the lift's with them),
  // the window of whitened innovations they are fitted to, and the test's threshold.
  std::vector<std::shared_ptr<const StartSchedule>> reopen_lift_;
  bool reopened_lift_ = false;  ///< the prior running re-opened the lift
  std::vector<StepSignature> sig_all_, sig_lift_;
  InnovationWindow step_window_;
  Eigen::VectorXd step_z_;
  double lift_threshold_ = 0.0;
  // step_corrects_input: the actuators' steps as disturbance directions (columns of
  // input_steps_ for the inputs in step_inputs_), their prior deviations, their
  // signature per noise scale and the step read.
  Eigen::MatrixXd input_steps_;
  std::vector<int> step_inputs_;
  Eigen::VectorXd input_prior_;
  std::vector<StepSignature> sig_input_;
  Eigen::VectorXd mu_input_;
  void correct_input_step(std::size_t at, double l_all);
  /// An input's direction is kept where [D E_c] v matches B_j within kInputMatch; its
  /// step's prior deviation is kInputStepStd of its largest limit, read where the window
  /// determines it to kInputDetermined of that; a step is the actuators' where their GLR
  /// is at least kInputExplained of every disturbance's; an input whose compensation
  /// would move a state by more than kInputKick of its bound in one period is not read.
  static constexpr double kInputMatch = 0.05, kInputStepStd = 0.1, kInputDetermined = 0.1, kInputExplained = 0.9,
                          kInputKick = 0.5;
  static constexpr int kStepWindow = 20;
  static constexpr double kLiftConfidence = 0.999;
  static constexpr double kStepMemory = 0.7, kStepThreshold = 16.0, kStepConfirm = 4.0, kReopenResidualStd = 3e-3;
  /// A step re-opens a force component whose target moves no state by more than
  /// kReopenTargetShift of its bound for kReopenForceStd (N), to that deviation.
  static constexpr double kReopenForceStd = 1.0, kReopenTargetShift = 0.05;
  /// Steps are read where the monitor's level is within kStepNoiseLevel times the noise
  /// scale flown, for the scales up to kStepScaleMax (each has its re-opened gains).
  static constexpr double kStepNoiseLevel = 1.5, kStepScaleMax = 4.0;
  static constexpr std::size_t kStepHold = 50;
  Eigen::VectorXd gate_prev_innov_;  ///< per measured row: last period's innovation (before any gating)
  bool gate_have_prev_ = false;      ///< gate_prev_innov_ is last period's
  Eigen::VectorXd u_min_, u_max_;
  ControlStep out_;
  long clipped_ = 0, fallbacks_ = 0, reverted_periods_ = 0;
  bool reverted_ = false;  ///< the reversion's hysteresis state (revert_beyond)
};

}  // namespace tmpc
