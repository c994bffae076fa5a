// The design configuration: vehicle parameters (model spec, set S1 or S2), the
// helix reference (thesis 6.2), constraints and weights (thesis 5.3), the
// disturbance schedule (thesis Table 6.1), simulation and solver settings.
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

/// Helix reference, thesis section 6.2:
/// x = cx + r cos(w t), y = cy + r sin(w t), z = z0 - a cos(w t), psi = psi_r.
struct HelixReference {
  double radius = 0.0;       // m
  double center_x = 0.0;     // m
  double center_y = 0.0;     // m
  double z_offset = 0.0;     // m
  double z_amplitude = 0.0;  // m
  double angular_rate = 0.0; // rad/s (pi/40 in the thesis)
  double yaw = 0.0;          // rad
  ReferenceAttitude attitude = ReferenceAttitude::Trim;
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
  double duration = 0.0;   // s, mission length
  double substep = 0.0;    // s, RK4 step of the plant
  std::string plant;       // "el" (Euler-Lagrange) or "mujoco"
};

/// Settings for the linear error model (thesis 5.2).
struct ErrorModelSettings {
  Discretization discretization = Discretization::Zoh;
  double lpv_sample_step = 0.0;  // s, sampling of the reference for the affinity check
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
};

/// Offline synthesis (thesis ch. 3; DESIGN.md section 4).
struct SynthesisSettings {
  std::string tube_gain;        // "lqr" | "lmi_thesis" | "lmi_robust"
  bool compare_gains = true;    // compute every gain's tube for the report
  std::string lmi_lambda;       // "search" or a number in (0, 1)
  double lmi_w_floor = 0.0;     // W >= w_floor I (normalized coordinates)
  bool lmi_vertices = true;     // LMIs at every LPV vertex (else nominal only)
  int lmi_certify_steps = 0;    // robust form: bisection steps for the largest W it certifies
  std::string rpi_variant;      // "lti" | "lpv_thesis" | "lpv_robust"
  double rpi_lambda = 0.0;      // relative error bound of (3.34)
  std::string w_source;         // "box" | "sampled"
  Eigen::Matrix<double, 24, 1> w_state_fraction;  // W_u half-widths / state half-widths
  Eigen::Vector3d w_disturbance = Eigen::Vector3d::Zero();  // N, half-widths of D (W_d = D_z D)
  int w_samples = 0;            // sampled W: number of samples
  double w_sample_fraction = 0.0;  // sampled W: mass/inertia perturbation
  double w_sample_box = 0.0;    // sampled W: error states drawn in this fraction of the state box
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

struct Config {
  std::string source;  // file the config came from (for messages)
  VehicleParams vehicle;
  HelixReference reference;
  double sample_time = 0.0;  // s, T
  Eigen::Vector4d input_min, input_max;              // absolute actuator limits
  Eigen::Matrix<double, 24, 1> state_error_max;      // half-widths of the error box X
  Eigen::Vector4d input_weights;                     // lambda (Sigma_lambda)
  Eigen::Matrix<double, 24, 1> state_weights;        // rho (Sigma_rho)
  std::vector<DisturbanceStep> disturbances;
  PerturbationSettings perturbation;
  SimulationSettings simulation;
  ErrorModelSettings error_model;
  SolverSettings solver;
  TubeLawSettings tube_law;       // optional section `tube_law` (defaults above)
  SynthesisSettings synthesis;
  ExplicitSettings explicit_mpc;  // optional section `explicit` (defaults above)
  LinkSettings link;              // optional section `link` (defaults above)
};

/// Largest horizon N (and M) a configuration or an artifact may give: the condensed
/// QP has (M m + N n) rows of M m entries.
constexpr int kMaxHorizon = 200;
/// Largest configuration (or scenario) file read, in bytes.
constexpr long kMaxConfigBytes = 1 << 20;

/// Load and validate a YAML config. Throws ConfigError naming file and key.
Config load_config(const std::string& path);
/// Same from a string (tests); `source` names it in messages.
Config load_config_from_string(const std::string& yaml, const std::string& source);
/// The text of a YAML file for a loader: a regular file of at most kMaxConfigBytes
/// (a directory, a device such as /dev/zero or a pipe is an error naming the path).
/// `what` names the kind of file in messages ("configuration", "scenario").
std::string read_config_file(const std::string& path, const char* what);

}  // namespace tmpc
