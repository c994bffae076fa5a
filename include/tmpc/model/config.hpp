// The design configuration: the plant model (the tiltrotor's vehicle parameters,
// model spec set S1 or S2, or a linear system), the trajectory envelope, constraints
// and weights (thesis 5.3), synthesis, solver, tube-law and link settings. A flight
// (trajectory, disturbances, noise, plant parameters) is a scenario file apart
// (sim/scenario.hpp).
//
// Every number of the case study lives in config/tiltrotor.yaml; nothing here has
// a case-study default. load_config() validates everything and throws ConfigError
// naming the file and the key (e.g. "tiltrotor.yaml: weights.state: expected 24
// values, got 23").
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/state_layout.hpp"

namespace tmpc {

/// Bad configuration input: the message names the file and the key.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where the rotor-group inertia of the config is taken about (model spec 7.1).
enum class RotorInertiaReference {
  Com,    ///< set S1: about the rotor-group CoM (physical, thesis-literal)
  Pivot,  ///< set S2: about the tilt pivot (Rego's linear model; not a rigid body)
};

/// Vehicle parameters (model spec sections 1-4; masses/inertias thesis Table 6.2).
struct VehicleParams {
  double gravity = 0.0;              // m/s^2, along -z of the inertial frame
  double load_mass = 0.0;            // kg
  Eigen::Matrix3d load_inertia;      // kg m^2, about the load CoM, load axes
  double rod_length = 0.0;           // m, load to rod top A1 along +z_L
  double body_mass = 0.0;            // kg
  Eigen::Matrix3d body_inertia;      // kg m^2, about the body CoM, B axes
  Eigen::Vector3d d_a1b;             // m, rod top A1 -> body origin B, B axes
  Eigen::Vector3d d_b1;              // m, body origin -> body CoM, B axes
  double rotor_mass = 0.0;           // kg, each rotor group
  Eigen::Matrix3d rotor_inertia;     // kg m^2, rotor axes, about com or pivot
  RotorInertiaReference rotor_inertia_reference = RotorInertiaReference::Com;
  Eigen::Vector3d rotor_com;         // m, pivot -> rotor-group CoM, rotor axes
  Eigen::Vector3d d_b_right;         // m, body origin -> right tilt pivot, B axes
  Eigen::Vector3d d_b_left;          // m, body origin -> left tilt pivot, B axes
  double dihedral = 0.0;             // rad, beta: rotor frames rolled by -+beta
  double drag_torque_ratio = 0.0;    // m, k_tau/b: rotor drag torque per thrust
  double spin_right = 0.0;           // +1 or -1, lambda_R
  double spin_left = 0.0;            // +1 or -1, lambda_L
  std::array<double, 10> friction{};  // N m s/rad (or N s/m), diagonal of L_fr

  /// Rotor-group inertia about its CoM in rotor axes (S2 shifted by parallel axes).
  Eigen::Matrix3d rotor_inertia_about_com() const;
};

/// Attitude of the reference (the coordinates that are not tracked).
enum class ReferenceAttitude {
  Trim,         ///< dynamically consistent: phi, theta, gamma, alpha trimmed for the acceleration
  Equilibrium,  ///< thesis-literal: held at the hover equilibrium; (5.4) then has a residual
};

/// The trajectories a design flies (DESIGN.md 2, issue "missions as data"): the LPV
/// vertices span the acceleration box (thesis (5.8): sigma = the load's reference
/// acceleration), the input box is tightened for every feedforward over it, and
/// `tmpc check` refuses a trajectory that leaves it. With `trajectories` (scenario
/// files) the box is the range of their accelerations, widened by `margin`.
struct EnvelopeSettings {
  Eigen::Vector3d acceleration_min = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Vector3d acceleration_max = Eigen::Vector3d::Zero();
  double speed_max = 0.0;       // m/s
  double yaw = 0.0;             // rad: the yaw the error model is linearized at
  double yaw_tolerance = 0.0;   // rad: a fixed-yaw design flies psi_r within yaw +- this
  /// rad/s; >= 0: any yaw whose rate stays within flies. The dynamics do not change
  /// when the whole system turns about the vertical, so the horizontal position,
  /// velocity and integral errors are taken in the reference's yaw frame (turned by
  /// psi_r - yaw) and the design's model holds at every psi_r; < 0: the fixed yaw.
  double yaw_rate_max = -1.0;
  bool any_yaw() const { return yaw_rate_max >= 0.0; }
  /// A world vector (acceleration, force) in the frame the design's model is written
  /// in: turned by -(psi_r - yaw) for an any-yaw design, as is otherwise.
  Eigen::Vector3d in_design_frame(const Eigen::Vector3d& v, double psi_r) const;
  /// "yaw 0 +- 0.05 rad" or "any yaw at up to 0.1 rad/s (from 0 rad: ...)".
  std::string yaw_text() const;
  std::vector<std::string> trajectories;  // scenario files (paths relative to the config)
  double margin = 0.1;          // relative widening of the box from `trajectories`
};

/// A constant force on the load switched on at `time` (thesis Table 6.1).
struct DisturbanceStep {
  double time = 0.0;                     // s
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N, inertial axes, added to earlier steps
};

/// Mass/inertia perturbations of the plant (thesis 6.5 Monte Carlo).
struct PerturbationSettings {
  double fraction = 0.0;       // relative half-range, e.g. 0.10
  std::string distribution;    // "uniform" or "normal" (fraction = 3 sigma, clipped)
  unsigned seed = 0;
  int runs = 0;
};

enum class Discretization { Zoh, Euler };

struct SimulationSettings {
  double substep = 0.0;    // s, RK4 step of the plant
};

/// Settings for the linear error model (thesis 5.2).
struct ErrorModelSettings {
  Discretization discretization = Discretization::Zoh;
  int envelope_grid = 0;  // points per axis of the acceleration box for the feedforward range and the affinity report
};

struct SolverSettings {
  double admm_epsilon = 0.0;  // thesis 6.4
  double admm_eta = 0.0;      // restart factor, Algorithm 4.2
};

/// The online tube law (thesis (5.9); runtime/tube_controller.hpp). Optional section
/// `tube_law`; without it, Mayne's law as in the thesis.
struct TubeLawSettings {
  bool offset_free = false;     // disturbance observer and steady-state targets
  double observer_gain = 0.1;   // beta in (0, 1]
  // Reversion to the tube gain's unconstrained law past the linear model's region
  // (runtime/tube_controller.hpp revert_beyond): enter past revert_beyond times a
  // state's bound (0: off, else > 1), leave within revert_within (in [1, revert_beyond]).
  double revert_beyond = 0.0;
  double revert_within = 1.5;
  /// The bounds' ranges (a NaN is in none), for these settings or any pair of bounds.
  static bool revert_beyond_valid(double beyond) { return beyond == 0.0 || beyond > 1.0; }
  static bool revert_within_valid(double beyond, double within) {
    return beyond == 0.0 || (within >= 1.0 && within <= beyond);
  }
  bool revert_beyond_valid() const { return revert_beyond_valid(revert_beyond); }
  bool revert_within_valid() const { return revert_within_valid(revert_beyond, revert_within); }
};

/// State estimation (optional section `estimation`; DESIGN.md 5b): which observer the
/// offset-free law uses and what it is designed for. Without the section: the one-step
/// residual observer of `tube_law`, every measured state, no output-feedback tube.
struct EstimationSettings {
  std::string observer = "residual";  ///< "residual" | "kalman"
  std::string measured = "all";       ///< "all" | "positions_angles_rates" (no linear velocities)
  /// Standard deviations of the measurement noise per state group (position m, angle
  /// rad, velocity m/s, angular rate rad/s): the Kalman filter's R.
  std::array<double, 4> noise{};
  double process_state_fraction = 3e-5;  ///< Q of the states: (fraction x half-width)^2 per step
  double process_force = 0.02;           ///< Q of the disturbance (N per step, random walk)
  double process_residual = 1e-3;        ///< Q of the residual channels (normalized per step)
  /// The filter's start (optional `start_prior`; estimator.hpp start_gains()): standard
  /// deviations of the force on the load (N) and of the residuals (normalized) the filter
  /// assumes when it is engaged, and the states' as a multiple of their measurement
  /// noise; all 0 (no `start_prior`): the steady-state gain from the start.
  double start_force = 0.0, start_residual = 0.0, start_state = 0.0;
  bool output_feedback_tube = false;     ///< tighten by the estimation error set too
  /// How the tube bounds the measurement noise (estimator.hpp): "bounded" (a box of
  /// noise_bound_sigmas standard deviations, Mayne et al. 2006) or "gaussian" (white
  /// Gaussian noise: noise_bound_sigmas standard deviations of the errors it causes).
  std::string output_feedback_noise = "bounded";
  bool gaussian_noise() const { return output_feedback_noise == "gaussian"; }
  double noise_bound_sigmas = 3.0;       ///< the tube's noise box: this many standard deviations
  double force_rate_bound = 0.02;        ///< the tube's bound on the force's change per step, N
  double residual_rate_bound = 0.0;      ///< the tube's bound on the residuals' change per step (normalized)
  /// The switched observer (optional `noise_monitor`; runtime/noise_monitor.hpp): the
  /// residual observer while the measured noise stays below monitor_residual_below times
  /// the noise the filter is designed for, the filter again above monitor_filter_above;
  /// averaged over monitor_window_s. 0: the filter always.
  double monitor_residual_below = 0.0, monitor_filter_above = 0.0, monitor_window_s = 1.0;
};

/// Soft state constraints (optional section `soft_constraints`; DESIGN.md 5b): an
/// infeasible QP is solved again with the state constraints softened by an exact L1
/// penalty (parametric_qp.hpp), inputs hard, instead of falling back to the LQR law.
struct SoftConstraintSettings {
  bool enabled = false;
  double penalty = 0.0;         ///< rho of the penalty (normalized); 0: from the design's multipliers
  double safety_factor = 10.0;  ///< automatic rho = this x the largest sum of multipliers sampled
};

/// Offline synthesis (thesis ch. 3; DESIGN.md section 4).
struct SynthesisSettings {
  std::string tube_gain;        // "lqr" | "lmi_thesis" | "lmi_robust"
  Eigen::VectorXd lqr_input_scale;  // the LQR tube gain's input weights: this times lambda (m; ones: the thesis')
  bool compare_gains = true;    // compute every gain's tube for the report
  std::string lmi_lambda;       // "search" or a number in (0, 1)
  double lmi_w_floor = 0.0;     // W >= w_floor I (normalized coordinates)
  bool lmi_vertices = true;     // LMIs at every LPV vertex (else nominal only)
  int lmi_certify_steps = 0;    // robust form: bisection steps for the largest W it certifies
  std::string rpi_variant;      // "lti" | "lpv_thesis" | "lpv_robust"
  double rpi_lambda = 0.0;      // relative error bound of (3.34)
  std::string w_source;         // "box" | "sampled"
  Eigen::VectorXd w_state_fraction;  // W_u half-widths / state half-widths (n entries)
  Eigen::VectorXd w_disturbance;  // half-widths of the disturbance box D, one per disturbance channel (W_d = D_z D)
  int w_samples = 0;            // sampled W: number of samples
  double w_sample_fraction = 0.0;  // sampled W: mass/inertia perturbation
  double w_sample_box = 0.0;    // sampled W: error states drawn in this fraction of the state box
  unsigned w_seed = 1;          // sampled W: random seed
  std::string terminal_cost;    // "lqr" | "lmi"
  int horizon = 0;              // N
  int control_horizon = 0;      // M <= N
  int verify_directions = 0;    // support-function directions for the invariance check
};

/// Explicit tube MPC (thesis 4.1): the mpQP's horizon and parameter box, build limits.
struct ExplicitSettings {
  int horizon = 2;               // N of the explicit QP
  int control_horizon = 1;       // M <= N
  double domain_fraction = 0.5;  // parameter box: this fraction of the tightened set x_bar
  int max_regions = 20000;
  double time_limit_s = 1800.0;
};

/// The serial link's safety rules (optional section `link`; DESIGN.md 5b, README
/// "Serial protocol"). Plausibility gates on the measured state, the watchdogs of
/// both sides and the protocol's session and sequence rules (io/protocol.hpp).
struct LinkSettings {
  int watchdog_periods = 10;        ///< controller: safe command after this many periods without a valid state
  double plant_hold_s = 0.1;        ///< plant: hold the last input this long without a valid control, then hover
  // Absolute bounds of a measured state (physical units) and of the time stamp.
  double bound_position = 1e3, bound_angle = 1.6, bound_yaw = 1e3, bound_velocity = 20.0, bound_rate = 20.0;
  double bound_time = 1e6;
  // Jump gate: largest change of the measured error against its one-period model
  // prediction, per group (physical units); 0: half of the group's widest half-width
  // of the error box (state_error_max).
  double jump_position = 0.0, jump_angle = 0.0, jump_velocity = 0.0, jump_rate = 0.0;
  double time_tolerance = 0.5;      ///< time stamps within this fraction of a period of the expected advance
  int gate_horizon = 50;            ///< periods: after a longer silence the jump gate has no prediction
  int resync_frames = 3;            ///< consecutive self-consistent rejected frames adopted as the new track
  int session_confirm = 2;          ///< consecutive frames of a new session before it is adopted
  int sequence_window = 1000;       ///< sequence numbers accepted ahead of the last one
};

/// The plant model a design is for: the tiltrotor (section `vehicle`, the default) or
/// a linear system given by its matrices (section `linear`), which regulates to the
/// origin; both go through the same synthesis and runtime.
enum class ModelKind { Tiltrotor, Linear };

/// x' = A x + B u + D d (continuous, physical units) with its states' names and kinds
/// and the measured states whose errors get integral states (thesis (5.6)).
struct LinearModelSpec {
  Eigen::MatrixXd A, B, D;
  std::vector<std::string> state_names, input_names;
  std::vector<StateKind> kinds;
  std::vector<int> integrated;  ///< indices of measured states
};

struct Config {
  std::string source;  // file the config came from (for messages)
  ModelKind model = ModelKind::Tiltrotor;
  VehicleParams vehicle;     // model tiltrotor
  LinearModelSpec linear;    // model linear
  ReferenceAttitude attitude = ReferenceAttitude::Trim;  // section `reference`
  EnvelopeSettings envelope;
  double sample_time = 0.0;  // s, T
  Eigen::VectorXd input_min, input_max;   // absolute actuator limits (m)
  Eigen::VectorXd state_error_max;        // half-widths of the error box X (n)
  Eigen::VectorXd input_weights;          // lambda (Sigma_lambda)
  Eigen::VectorXd input_rate_weights;     // weights.input_rate: on (u(k) - u(k-1))^2 (m, >= 0; zeros: none)
  Eigen::VectorXd state_weights;          // rho (Sigma_rho)
  SimulationSettings simulation;
  ErrorModelSettings error_model;
  SolverSettings solver;
  TubeLawSettings tube_law;       // optional section `tube_law` (defaults above)
  EstimationSettings estimation;  // optional section `estimation` (defaults above)
  SoftConstraintSettings soft_constraints;  // optional section `soft_constraints`
  SynthesisSettings synthesis;
  ExplicitSettings explicit_mpc;  // optional section `explicit` (defaults above)
  LinkSettings link;              // optional section `link` (defaults above)

  /// Measured states (20 for the tiltrotor: q, q'), integral states, all states, inputs.
  int measured() const;
  int integrals() const;
  int states() const { return measured() + integrals(); }
  int inputs() const;
  /// The measured states whose errors are integrated (tiltrotor: x, y, z, psi).
  std::vector<int> integrated() const;
  /// Names and kinds of the n error states, the names of the inputs.
  std::vector<std::string> state_names() const;
  std::vector<StateKind> state_kinds() const;
  std::vector<std::string> input_names() const;
};

/// Largest horizon N (and M) a configuration or an artifact may give: the condensed
/// QP has (M m + N n) rows of M m entries.
constexpr int kMaxHorizon = 200;
/// Largest configuration (or scenario) file read, in bytes.
constexpr long kMaxConfigBytes = 1 << 20;

/// Load and validate a YAML config. Throws ConfigError naming file and key.
Config load_config(const std::string& path);
/// The text of a configuration file with its `base` resolved: a file with the key
/// `base: FILE` (relative to it) is that file with its own keys laid over it, mapping
/// by mapping (a value replaces, a mapping merges); up to 4 levels. Without `base`,
/// the file's text as written. This is the text a design embeds in its artifact.
std::string read_config_text(const std::string& path);
/// Same from a string (tests); `source` names it in messages.
Config load_config_from_string(const std::string& yaml, const std::string& source);
/// The text of a YAML file for a loader: a regular file of at most kMaxConfigBytes
/// (a directory, a device such as /dev/zero or a pipe is an error naming the path).
/// `what` names the kind of file in messages ("configuration", "scenario").
std::string read_config_file(const std::string& path, const char* what);

}  // namespace tmpc
