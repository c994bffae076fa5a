// The explicit tube MPC law of one controller artifact: the partition of the nominal
// QP (4.7) at horizon (N, M) over a box of nominal states, its affine laws, and the
// search tree; stored next to the artifact in a companion file (.tmpcx: same record
// container, its own magic and version, bound to the artifact by the artifact's CRC-32).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/explicit/mpqp.hpp"
#include "tmpc/explicit/point_location.hpp"
#include "tmpc/sets/box.hpp"

namespace tmpc {

struct ControllerArtifact;

constexpr std::uint32_t kExplicitVersion = 1;

struct ExplicitOptions {
  int N = 1, M = 1;              ///< horizon and control horizon of the explicit QP
  double domain_fraction = 1.0;  ///< the parameter box: this fraction of the tightened set x_bar, about its center
  MpQpOptions mpqp;
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

struct ExplicitLaw {
  int n = 0, nz = 0, N = 0, M = 0;
  double domain_fraction = 1.0;
  Box domain;
  RegionTable table;
  std::vector<double> Kz, kz;    ///< per region: nz x n row-major, then nz
  SearchTree tree;
  std::uint32_t artifact_crc = 0;
  MpQpStats stats;               ///< of the mpQP build
  int regions() const { return table.regions(); }
  /// z = Kz_i th + kz_i into z (size nz), no allocation.
  void evaluate(int region, const Eigen::VectorXd& th, Eigen::VectorXd& z) const;
  /// Bytes of the online data (regions, laws, tree).
  std::size_t memory_bytes() const;
};

/// The mpQP of the artifact's nominal QP at (N, M) over the domain box.
MpQp explicit_mpqp(const ControllerArtifact& a, const ExplicitOptions& o);
ExplicitLaw build_explicit_law(const ControllerArtifact& a, const ExplicitOptions& o);
ExplicitLaw make_explicit_law(const Partition& part, int N, int M, double domain_fraction, std::uint32_t artifact_crc);

/// CRC-32 of the artifact's serialized form (what binds a companion file to it).
std::uint32_t artifact_checksum(const ControllerArtifact& a);

std::vector<std::uint8_t> serialize_explicit(const ExplicitLaw& law);
ExplicitLaw deserialize_explicit(const std::vector<std::uint8_t>& bytes, const std::string& source);
void save_explicit(const ExplicitLaw& law, const std::string& path);
/// Throws RecordFileError if the file is bad or, when `a` is given, belongs to another artifact.
ExplicitLaw load_explicit(const std::string& path, const ControllerArtifact* a = nullptr);
/// The companion path of an artifact path: FILE.tmpc -> FILE.tmpcx.
std::string explicit_path_for(const std::string& artifact_path);

}  // namespace tmpc
