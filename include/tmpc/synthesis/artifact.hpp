// The controller artifact: one binary file with everything the online controller
// needs, versioned and checksummed; the runtime reads its records and never parses
// the YAML it came from (kept as the record `config`, for provenance and the checks).
//
//   offset 0   8 bytes  magic "TMPCART\0"
//          8   u32      format version (kArtifactVersion)
//         12   u64      payload length P
//         20   P bytes  records: u16 name length, name, u8 kind, then
//                         kind 1 (matrix): u32 rows, u32 cols, rows*cols f64, column-major
//                         kind 2 (text):   u64 length, bytes
//                         kind 3 (int):    i64
//     20 + P   u32      CRC-32 (IEEE 802.3) of bytes [0, 20 + P)
// All integers little-endian, f64 IEEE-754. Records (version 2): the design (model,
// weights, sets, gains, tube), the plant model (its kind, the tiltrotor's vehicle
// parameters or the linear model's matrices), dimensions and the states' names and
// kinds, the input limits, the trajectory envelope with the feedforward range it was
// tightened for, and the solver, tube-law and link settings. Loading rejects a wrong
// magic or version, a truncated or extended file, a checksum mismatch, an unknown or
// malformed record, every dimension mismatch, and what the records do not mean
// (check_artifact), with a message naming it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/checksum.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/qp/disturbance_target.hpp"
#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/sets/box.hpp"
#include "tmpc/sets/zonotope.hpp"
#include "tmpc/synthesis/estimator.hpp"
#include "tmpc/synthesis/record_file.hpp"

namespace tmpc {

constexpr std::uint32_t kArtifactVersion = 8;

/// Every artifact read or write error (the record container's error type).
using ArtifactError = RecordFileError;

struct ControllerDesign;

/// Immutable controller model, normalized coordinates (x_n = N_x x, u_n = N_u u).
struct ControllerArtifact {
  std::string config_text;       ///< the YAML the design came from (provenance)
  std::string tube_gain, rpi_variant, terminal_cost;
  double sample_time = 0.0;
  int n = 0, m = 0, N = 0, M = 0;
  // The plant model and its states.
  ModelKind model = ModelKind::Tiltrotor;
  int measured = 0;                        ///< states in a state frame (n - integrals)
  std::vector<int> integrated;             ///< measured states whose errors are integrated
  std::vector<std::string> state_names, input_names;
  std::vector<StateKind> kinds;            ///< n entries
  VehicleParams vehicle;                   ///< model tiltrotor
  ReferenceAttitude attitude = ReferenceAttitude::Trim;
  Eigen::MatrixXd linear_A, linear_B, linear_D;  ///< model linear (continuous, physical)
  double substep = 0.0;                    ///< the plant's RK4 step of the design config
  // Limits and the envelope.
  Eigen::VectorXd input_min, input_max;    ///< absolute actuator limits (physical)
  EnvelopeSettings envelope;               ///< the acceleration box, speed, yaw (tiltrotor)
  Eigen::VectorXd feedforward_min, feedforward_max;  ///< u_r range U was tightened for
  // Online settings.
  SolverSettings solver;
  TubeLawSettings tube_law;
  LinkSettings link;
  // The design.
  Eigen::VectorXd N_x, N_u;
  Eigen::MatrixXd A, B, D;       ///< nominal model
  std::vector<Eigen::MatrixXd> A_vertices;
  Eigen::MatrixXd K, K_lqr, P_lqr, L;
  Eigen::MatrixXd Sigma_rho, Sigma_lambda;
  Eigen::MatrixXd Sigma_delta;   ///< input-rate weight (m x m, normalized; zero: none; mpc_qp.hpp)
  bool rate_weighted() const { return Sigma_delta.size() > 0 && !Sigma_delta.isZero(0.0); }
  Box X, U, x_bar, u_bar;
  Zonotope Z, W;
  Eigen::VectorXd u_eq;          ///< hover inputs (physical; zero for a linear model)
  Eigen::VectorXd angles_eq;     ///< hover gamma_1, gamma_2, alpha_r, alpha_l (tiltrotor)
  double margin = 0.0;
  // State estimation (config `estimation`, synthesis/estimator.hpp): "residual" (the
  // one-step residual observer) or "kalman" with its measured rows, residual channels
  // E_c and gain L_kf ((n + nd + nc) x rows); the output-feedback tube's figures (0 and
  // empty without it: Z is then the state tube).
  std::string estimator = "residual";
  std::vector<int> estimator_rows;
  Eigen::MatrixXd estimator_E_c, estimator_L;
  /// The filter's measurement noise (standard deviations on estimator_rows, normalized)
  /// and its noise monitor (runtime/noise_monitor.hpp): residual_below, filter_above,
  /// window (s); residual_below 0: the filter always.
  Eigen::VectorXd estimator_noise;
  Eigen::Vector3d estimator_monitor = Eigen::Vector3d(0.0, 0.0, 1.0);
  /// The filter's covariances (its DARE's a-priori P and the process noise Q, both
  /// (n + nd + nc) square; R is diag(estimator_noise^2)) and its start prior (force std
  /// in N, residual std normalized, states' std in multiples of their noise; zeros: the
  /// steady gain from the start): the gains of the filter's first periods after a reset
  /// (estimator.hpp start_covariance(), start_gains()).
  Eigen::MatrixXd estimator_P, estimator_Q;
  Eigen::Vector3d estimator_start = Eigen::Vector3d::Zero();
  bool filter_start_scheduled() const { return estimator == "kalman" && (estimator_start.array() > 0.0).any(); }
  bool switched_observer() const { return estimator == "kalman" && estimator_monitor(0) > 0.0; }
  double noise_margin = 0.0;                ///< output-feedback tube: noise scale with non-empty sets
  Eigen::VectorXd estimation_error_radius;  ///< output-feedback tube: half-widths of E_x (normalized)
  /// Soft state constraints (config `soft_constraints`): the exact L1 penalty of the
  /// softened QP, normalized; 0: hard constraints only. make_artifact() takes the
  /// configured value; an automatic one (penalty 0) comes from calibrate_soft_penalty()
  /// (solvers/soft_penalty.hpp), which `tmpc design` runs.
  double soft_penalty = 0.0;
  bool soft_constraints = false;            ///< the config enables them
  /// Rows of the hard QP certified by LPs never to bind (qp/redundant_rows.hpp) for the
  /// nominal form (x0 in X_bar) and the offset-free form (also |d| <= certificate_d_max,
  /// |c| <= certificate_c_max: every force whose steady state fits the tightened sets
  /// along each axis, the residual within W's box); the active-set solver leaves them
  /// out there. certify_redundant_rows() computes them (make_artifact() calls it).
  std::vector<int> redundant_rows, redundant_rows_offset_free;
  Eigen::VectorXd certificate_d_max, certificate_c_max;
  void certify_redundant_rows();

  /// QP data (3.50)-(3.55) rebuilt from the stored model, weights and sets; with
  /// `offset_free`, in coordinates around the steady state of the disturbance d
  /// (parameter (x_bar - x_s, d, c), disturbance_target()); with `soft`, the state
  /// constraints softened by soft_penalty (parametric_qp.hpp; needs soft_penalty > 0).
  MpcQpData qp(bool offset_free = false, bool soft = false) const;
  /// The steady state of a constant disturbance d with zero tracked and integral
  /// errors: x_s = Tx d, u_s = Tu d (normalized), from A, B, D.
  DisturbanceTarget disturbance_target() const;
  /// The states whose steady-state error the offset-free law keeps at zero: the
  /// integrated measured states and the integral states.
  std::vector<int> tracked_states() const;
  /// Kinds of the measured states (the first `measured` of `kinds`).
  std::vector<StateKind> measured_kinds() const { return {kinds.begin(), kinds.begin() + measured}; }
  /// The measured states of kind Velocity: the rows the force observer reads.
  std::vector<int> velocity_rows() const;
};

ControllerArtifact make_artifact(const ControllerDesign& d);

/// The Kalman filter's augmented model rebuilt from the artifact (A, B, D, E_c and the
/// measured rows; synthesis/estimator.hpp), and its error map (I - L C) A_a.
KalmanDesign kalman_model(const ControllerArtifact& a);
Eigen::MatrixXd estimation_error_map(const ControllerArtifact& a);

/// What the records must mean before anything runs; throws ArtifactError naming the
/// source, the record and the value: supported dimensions (n <= 48 states in total,
/// the measured ones and their kinds, m <= 16 inputs) consistent in every record,
/// 1 <= M <= N <= kMaxHorizon, a sample time in [1e-5, 1] s, positive scalings,
/// non-empty sets with the tightened ones inside theirs, a convex cost (H positive
/// definite), a tube gain stabilizing the nominal model and every vertex, a stabilizing
/// LQR fallback, a margin >= 1, input limits that contain the feedforward range, a
/// valid link and tube-law setting, and an embedded configuration that is valid and
/// agrees with the records (sample time, horizons, scalings, limits, the gain and set
/// variants, the vehicle and its hover equilibrium). deserialize_artifact() runs it.
void check_artifact(const ControllerArtifact& a, const std::string& source);

std::vector<std::uint8_t> serialize_artifact(const ControllerArtifact& a);
/// `source` names the data in error messages (a file name).
ControllerArtifact deserialize_artifact(const std::vector<std::uint8_t>& bytes, const std::string& source);

void save_artifact(const ControllerArtifact& a, const std::string& path);
ControllerArtifact load_artifact(const std::string& path);

}  // namespace tmpc
