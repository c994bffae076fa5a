// Closed-loop missions on a virtual clock (thesis 6.2, generalized): a scenario (its
// trajectory, disturbances, sensor noise, plant and Monte Carlo draws) flown with the
// tube controller and any solver, checked against the artifact's envelope first; and
// the thesis' metrics: RMSE per measured state, total control variation per input,
// solve-time statistics, fallbacks, clipping, tube exits (in total and per window; a
// window starts at each of the scenario's disturbance events) and state-constraint
// violations of the true state (not the noisy measurement; the integral rows, which
// exist only in the controller, are its own integrators).
#pragma once

#include <string>
#include <vector>

#include "tmpc/runtime/estimator_choice.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct MissionOptions {
  std::string solver = "active-set";
  std::string plant;              ///< "" (the scenario's), "el" or "mujoco"
  double duration = 0.0;          ///< > 0: shorter than the scenario's
  int run = -1;                   ///< Monte Carlo run (the scenario's plant.random), -1: none
  long seed = -1;                 ///< its seed, -1: the scenario's
  bool reinitialize_nominal = false;
  bool reference_join = true;     ///< join the reference from a start off it (runtime/reference_join.hpp)
  std::string tube_law;           ///< "" (the artifact's), "mayne" or "offset-free"
  EstimatorChoice estimator;      ///< the observer and the filter's adaptations (runtime/estimator_choice.hpp)
  std::string telemetry_csv;      ///< one row per period when not empty
  std::string explicit_law;       ///< companion file for solver "explicit"
  const VehicleParams* plant_vehicle = nullptr;  ///< the plant's vehicle (null: the artifact's)
  /// Turn the reference's yaw into the force on the load (runtime/yaw_governor.hpp):
  /// the mission's yaw is free. Needs an any-yaw tiltrotor design.
  bool yaw_into_force = false;
  /// When set, every period's QP parameter (what the solver was given) is appended:
  /// the mission's QPs, for tests and benchmarks.
  std::vector<Eigen::VectorXd>* record_qps = nullptr;
};

struct MissionMetrics {
  std::vector<std::string> state_names, input_names;  ///< of the measured states and the inputs
  std::vector<double> rmse;              ///< per measured state, true error
  std::vector<double> max_abs_error;     ///< per measured state, true error
  std::vector<double> tcv;               ///< per input: sum |u_k - u_(k-1)|
  double solve_min = 0, solve_mean = 0, solve_p50 = 0, solve_p99 = 0, solve_max = 0;  ///< us
  double iterations_mean = 0;
  int iterations_max = 0;
  long periods = 0, deadline_misses = 0, fallback_periods = 0, clipped_periods = 0;
  long reverted_periods = 0;  ///< of the fallback periods: the error past the reversion bound (revert_beyond)
  long tube_exits = 0, state_constraint_violations = 0;
  /// How far the true state went outside the box: the largest |x_i| / half-width_i
  /// (above 1: a violation) and the state; 0 and "" without one.
  double violation_max_ratio = 0.0;
  std::string violation_worst_state;
  /// Per state of the box (all n, the artifact's names in box_names): the largest
  /// |x_i| / half-width_i over the flight, violations or not (e.g. the servo-rate peak
  /// as a fraction of its bound).
  std::vector<std::string> box_names;
  std::vector<double> box_peak_ratio;
  /// Periods flown with the softened QP (the hard QP infeasible), the largest slack in
  /// physical units and its state.
  long softened_periods = 0;
  double slack_max = 0.0;
  /// Yaw into the force (MissionOptions::yaw_into_force): the largest offset of the
  /// reference's yaw from the mission's (rad) and the periods it was turning or turned.
  double yaw_offset_max = 0.0;
  long yaw_governed_periods = 0;
  std::string slack_worst_state;
  std::vector<double> window_starts;        ///< 0, then each disturbance event's start
  std::vector<long> tube_exits_per_step;    ///< per window
  /// Largest distance from the tube in each window, in radii of Z (<= 1: inside), and
  /// the error state that set it most often while outside.
  std::vector<double> tube_ratio_max_per_step;
  /// Seconds from the window's start to the end of its last period outside the tube:
  /// how long the transient lasted (0: no exit).
  std::vector<double> tube_settle_s_per_step;
  std::string tube_worst_state;
  std::vector<double> d_hat_final;          ///< offset-free: the disturbance estimate at the end
  std::string solver, plant, scenario;
  std::string estimator;                    ///< "residual", "kalman" or "switched" (offset-free law)
  long filtered_periods = 0;                ///< periods flown on the Kalman filter's estimate
  std::vector<double> join_offset;          ///< the reference join's g0 (m, its position rows; empty: no join)
  double join_duration = 0.0;               ///< its T (s)
  long observer_switches = 0;               ///< switched observer: changes between filter and measurement
  long gated_samples = 0;                   ///< measured rows the filter's innovation gate replaced (glitches)
  long step_detections = 0;                 ///< disturbance steps detected that re-opened the filter's gains (step_detection)
  long step_lift_reopenings = 0;            ///< of those, the steps that re-opened the lift (step_reopens_lift)
  long step_actuator_corrections = 0;       ///< of those, the steps read as the actuators' (step_corrects_input)
  long step_late_kept = 0;  ///< steps detected older than the detection window, left to the steady gain (late_step_keeps_gain)
  double noise_level_max = 0.0;             ///< the noise monitor's largest level (switched; kalman with the adaptive gain)
  long filter_louder_periods = 0;           ///< filtered periods whose steady gain is chosen for louder noise than the design's
  double filter_noise_scale_max = 1.0;      ///< the loudest noise (times the design's) a flown gain was for
  bool offset_free = false;                 ///< the tube law flown
  bool noisy = false;                       ///< the scenario's sensors are noisy
  bool diverged = false;                    ///< the state became non-finite or left 10x the box
};

/// Throws std::invalid_argument when the scenario's trajectory is outside the
/// artifact's envelope (preflight.hpp) or does not fit the model.
MissionMetrics run_mission(const ControllerArtifact& a, const Scenario& s, const MissionOptions& o);
std::string metrics_json(const MissionMetrics& m);

}  // namespace tmpc
