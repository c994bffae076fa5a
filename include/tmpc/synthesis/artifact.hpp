// The controller artifact: one binary file with everything the online controller
// needs, versioned and checksummed.
//
//   offset 0   8 bytes  magic "TMPCART\0"
//          8   u32      format version (kArtifactVersion)
//         12   u64      payload length P
//         20   P bytes  records: u16 name length, name, u8 kind, then
//                         kind 1 (matrix): u32 rows, u32 cols, rows*cols f64, column-major
//                         kind 2 (text):   u64 length, bytes
//                         kind 3 (int):    i64
//     20 + P   u32      CRC-32 (IEEE 802.3) of bytes [0, 20 + P)
// All integers little-endian, f64 IEEE-754. Loading rejects a wrong magic or
// version, a truncated or extended file, a checksum mismatch, an unknown or
// malformed record and every dimension mismatch, with a message naming it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/checksum.hpp"
#include "tmpc/qp/disturbance_target.hpp"
#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/sets/box.hpp"
#include "tmpc/sets/zonotope.hpp"
#include "tmpc/synthesis/record_file.hpp"

namespace tmpc {

constexpr std::uint32_t kArtifactVersion = 1;

/// Every artifact read or write error (the record container's error type).
using ArtifactError = RecordFileError;

struct ControllerDesign;

/// Immutable controller model, normalized coordinates (x_n = N_x x, u_n = N_u u).
struct ControllerArtifact {
  std::string config_text;       ///< the YAML the design came from
  std::string tube_gain, rpi_variant, terminal_cost;
  double sample_time = 0.0;
  int n = 0, m = 0, N = 0, M = 0;
  Eigen::VectorXd N_x, N_u;
  Eigen::MatrixXd A, B, D;       ///< nominal model
  std::vector<Eigen::MatrixXd> A_vertices;
  Eigen::MatrixXd K, K_lqr, P_lqr, L;
  Eigen::MatrixXd Sigma_rho, Sigma_lambda;
  Box X, U, x_bar, u_bar;
  Zonotope Z, W;
  Eigen::Vector4d u_eq;          ///< hover inputs (physical)
  Eigen::Vector4d angles_eq;     ///< hover gamma_1, gamma_2, alpha_r, alpha_l
  double margin = 0.0;

  /// QP data (3.50)-(3.55) rebuilt from the stored model, weights and sets; with
  /// `offset_free`, in coordinates around the steady state of the load force d
  /// (parameter (x_bar - x_s, d), disturbance_target()).
  MpcQpData qp(bool offset_free = false) const;
  /// The steady state of a constant force d on the load (newtons) with zero position,
  /// yaw and integral errors: x_s = Tx d, u_s = Tu d (normalized), from A, B, D.
  DisturbanceTarget disturbance_target() const;
};

ControllerArtifact make_artifact(const ControllerDesign& d);

/// What the records must mean before anything runs; throws ArtifactError naming the
/// source, the record and the value: dimensions this build supports (24 states, 4
/// inputs), 1 <= M <= N <= kMaxHorizon, a sample time in [1e-5, 1] s, positive
/// scalings, non-empty sets with the tightened ones inside theirs, a convex cost (H
/// positive definite), a tube gain stabilizing the nominal model and every vertex, a
/// stabilizing LQR fallback, a margin >= 1, and an embedded configuration that is valid
/// and agrees with the records (sample time, horizons, scalings, the gain and set
/// variants, the hover equilibrium of its vehicle). deserialize_artifact() runs it.
void check_artifact(const ControllerArtifact& a, const std::string& source);

std::vector<std::uint8_t> serialize_artifact(const ControllerArtifact& a);
/// `source` names the data in error messages (a file name).
ControllerArtifact deserialize_artifact(const std::vector<std::uint8_t>& bytes, const std::string& source);

void save_artifact(const ControllerArtifact& a, const std::string& path);
ControllerArtifact load_artifact(const std::string& path);

}  // namespace tmpc
