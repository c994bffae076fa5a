// Explicit law: build from the artifact, evaluate, and the companion file.
#include "tmpc/explicit/explicit_law.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tmpc/model/checksum.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/qp/parametric_qp.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/record_file.hpp"

namespace tmpc {

namespace {
constexpr FileMagic kMagic = {'T', 'M', 'P', 'C', 'E', 'X', 'P', '\0'};
}  // namespace

void ExplicitOptions::validate() const {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("explicit options: " + what);
  };
  need(N >= 1, "horizon must be >= 1 (got " + std::to_string(N) + ")");
  need(M >= 1 && M <= N, "control_horizon must be in [1, horizon] (got " + std::to_string(M) + ")");
  need(domain_fraction > 0.0 && domain_fraction <= 1.0, "domain_fraction must be in (0, 1]");
  need(mpqp.max_regions >= 1, "max_regions must be >= 1");
  need(mpqp.time_limit_s > 0.0, "time_limit_s must be positive");
  need(mpqp.coverage_passes >= 1 && mpqp.coverage_samples >= 1, "coverage passes and samples must be >= 1");
}

MpQp explicit_mpqp(const ControllerArtifact& a, const ExplicitOptions& o) {
  o.validate();
  if (a.rate_weighted()) {
    throw std::invalid_argument("explicit MPC: the design has an input-rate weight (weights.input_rate), whose previous "
                                "input would be m more parameters of the partition; the explicit law does not solve "
                                "that form: design without it for explicit MPC");
  }
  const MpcQpData d = build_mpc_qp(a.A, a.B, a.Sigma_rho, a.Sigma_lambda, a.L, a.x_bar, a.u_bar, o.N, o.M);
  const Eigen::VectorXd c = a.x_bar.center(), h = 0.5 * o.domain_fraction * (a.x_bar.hi - a.x_bar.lo);
  return MpQp::from_parametric(ParametricQp::from_mpc(d), Box(c - h, c + h));
}

ExplicitLaw build_explicit_law(const ControllerArtifact& a, const ExplicitOptions& o) {
  const Partition part = solve_mpqp(explicit_mpqp(a, o), o.mpqp);
  return make_explicit_law(part, o.N, o.M, o.domain_fraction, artifact_checksum(a));
}

ExplicitLaw make_explicit_law(const Partition& part, int N, int M, double domain_fraction, std::uint32_t artifact_crc) {
  ExplicitLaw law;
  law.n = static_cast<int>(part.domain.lo.size());
  law.nz = part.regions.empty() ? 0 : static_cast<int>(part.regions.front().Kz.rows());
  law.N = N;
  law.M = M;
  law.domain_fraction = domain_fraction;
  law.domain = part.domain;
  law.table = RegionTable::from(part.regions);
  law.table.n = law.n;
  for (const CriticalRegion& r : part.regions) {
    for (Eigen::Index i = 0; i < r.Kz.rows(); ++i) {
      for (Eigen::Index j = 0; j < r.Kz.cols(); ++j) law.Kz.push_back(r.Kz(i, j));
    }
    for (Eigen::Index i = 0; i < r.kz.size(); ++i) law.kz.push_back(r.kz(i));
  }
  law.tree = SearchTree::build(part.regions, part.domain);
  law.artifact_crc = artifact_crc;
  law.stats = part.stats;
  return law;
}

void ExplicitLaw::evaluate(int region, const Eigen::VectorXd& th, Eigen::VectorXd& z) const {
  const std::size_t base = static_cast<std::size_t>(region) * static_cast<std::size_t>(nz);
  for (int i = 0; i < nz; ++i) {
    const double* row = Kz.data() + (base + static_cast<std::size_t>(i)) * static_cast<std::size_t>(n);
    double v = kz[base + static_cast<std::size_t>(i)];
    for (int j = 0; j < n; ++j) v += row[j] * th(j);
    z(i) = v;
  }
}

std::size_t ExplicitLaw::memory_bytes() const {
  return sizeof(double) * (table.H.size() + table.k.size() + Kz.size() + kz.size() + tree.hp.size() + tree.hb.size()) +
         sizeof(int) * (table.row_begin.size() + tree.leaf_regions.size()) + sizeof(SearchTree::Node) * tree.nodes.size();
}

std::uint32_t artifact_checksum(const ControllerArtifact& a) {
  // The CRC over the whole file would be CRC-32's constant residue: hash the content.
  const std::vector<std::uint8_t> b = serialize_artifact(a);
  return crc32(b.data(), b.size() - 4);
}

std::string explicit_path_for(const std::string& artifact_path) { return artifact_path + "x"; }

namespace {

Eigen::MatrixXd as_matrix(const std::vector<double>& v, Eigen::Index cols) {
  const Eigen::Index rows = cols > 0 ? static_cast<Eigen::Index>(v.size()) / cols : 0;
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) m(i, j) = v[static_cast<std::size_t>(i * cols + j)];
  }
  return m;
}

std::vector<double> as_vector(const Eigen::MatrixXd& m) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(m.size()));
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) v.push_back(m(i, j));
  }
  return v;
}

}  // namespace

std::vector<std::uint8_t> serialize_explicit(const ExplicitLaw& law) {
  RecordWriter w;
  w.integer("n", law.n);
  w.integer("nz", law.nz);
  w.integer("N", law.N);
  w.integer("M", law.M);
  w.integer("regions", law.regions());
  w.integer("artifact_crc", law.artifact_crc);
  w.matrix("domain_fraction", Eigen::MatrixXd::Constant(1, 1, law.domain_fraction));
  w.matrix("domain_lo", law.domain.lo);
  w.matrix("domain_hi", law.domain.hi);
  w.matrix("H", as_matrix(law.table.H, law.n));
  w.matrix("k", as_matrix(law.table.k, 1));
  w.matrix("row_begin", as_matrix(std::vector<double>(law.table.row_begin.begin(), law.table.row_begin.end()), 1));
  w.matrix("Kz", as_matrix(law.Kz, law.n));
  w.matrix("kz", as_matrix(law.kz, 1));
  w.matrix("tree_hp", as_matrix(law.tree.hp, law.n));
  w.matrix("tree_hb", as_matrix(law.tree.hb, 1));
  std::vector<double> nodes;
  for (const SearchTree::Node& nd : law.tree.nodes) {
    for (int v : {nd.hyperplane, nd.left, nd.right, nd.leaf_begin, nd.leaf_end}) nodes.push_back(v);
  }
  w.matrix("tree_nodes", as_matrix(nodes, 5));
  w.matrix("tree_leaf_regions",
           as_matrix(std::vector<double>(law.tree.leaf_regions.begin(), law.tree.leaf_regions.end()), 1));
  const SearchTreeStats& t = law.tree.stats;
  w.matrix("tree_stats", (Eigen::MatrixXd(1, 7) << t.nodes, t.leaves, t.depth, t.hyperplanes, t.lps, t.max_leaf_regions,
                          t.seconds).finished());
  const MpQpStats& s = law.stats;
  w.matrix("build_stats", (Eigen::MatrixXd(1, 11) << s.complete, s.seconds, s.qp_solves, s.lps, s.lower_dimensional,
                           s.licq_reduced, s.perturbed, s.unresolved_facets, s.holes_found, s.coverage_checked, 0.0)
                              .finished());
  w.text("stop_reason", s.stop_reason);
  return w.seal(kMagic, kExplicitVersion);
}

ExplicitLaw deserialize_explicit(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  RecordReader r(bytes, kMagic, kExplicitVersion, source, "explicit MPC law");
  ExplicitLaw law;
  law.n = r.integer("n", 1, 1000);
  law.nz = r.integer("nz", 1, 100 * kMaxHorizon);
  law.N = r.integer("N", 1, kMaxHorizon);
  law.M = r.integer("M", 1, law.N);
  const int regions = r.integer("regions", 0, 1 << 24);
  law.artifact_crc = static_cast<std::uint32_t>(r.integer("artifact_crc", 0, 0xffffffffLL));
  law.domain_fraction = r.matrix("domain_fraction", 1, 1)(0, 0);
  if (!(law.domain_fraction > 0.0 && law.domain_fraction <= 1.0)) {
    std::ostringstream os;
    os << "record 'domain_fraction' is " << law.domain_fraction << ", must be in (0, 1]";
    r.fail(os.str());
  }
  law.domain = Box(r.matrix("domain_lo", law.n, 1), r.matrix("domain_hi", law.n, 1));
  const Eigen::MatrixXd& rb = r.matrix("row_begin", regions + 1, 1);
  auto index = [&](double v, long long lo, long long hi, const std::string& what) {
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
      r.fail(what + " holds " + std::to_string(v) + ", not an index in [" + std::to_string(lo) + ", " +
             std::to_string(hi) + "]");
    }
    return static_cast<int>(v);
  };
  law.table.n = law.n;
  for (Eigen::Index i = 0; i < rb.rows(); ++i) {
    law.table.row_begin.push_back(index(rb(i, 0), i == 0 ? 0 : law.table.row_begin.back(), 1LL << 30, "row_begin"));
  }
  if (law.table.row_begin.front() != 0) r.fail("row_begin must start at 0");
  const int rows = law.table.row_begin.back();
  law.table.H = as_vector(r.matrix("H", rows, law.n));
  law.table.k = as_vector(r.matrix("k", rows, 1));
  law.Kz = as_vector(r.matrix("Kz", static_cast<Eigen::Index>(regions) * law.nz, law.n));
  law.kz = as_vector(r.matrix("kz", static_cast<Eigen::Index>(regions) * law.nz, 1));
  const Eigen::MatrixXd& hb = r.matrix("tree_hb", -1, 1);
  law.tree.hb = as_vector(hb);
  law.tree.hp = as_vector(r.matrix("tree_hp", hb.rows(), law.n));
  const Eigen::MatrixXd& leaves = r.matrix("tree_leaf_regions", -1, 1);
  for (Eigen::Index i = 0; i < leaves.rows(); ++i) {
    law.tree.leaf_regions.push_back(index(leaves(i, 0), 0, regions - 1, "tree_leaf_regions"));
  }
  const Eigen::MatrixXd& nodes = r.matrix("tree_nodes", -1, 5);
  if (nodes.rows() < 1) r.fail("the tree has no node");
  const long long nn = nodes.rows(), nh = hb.rows(), nl = leaves.rows();
  for (Eigen::Index i = 0; i < nodes.rows(); ++i) {
    SearchTree::Node nd;
    nd.hyperplane = index(nodes(i, 0), -1, nh - 1, "tree_nodes hyperplane");
    // Children come after their parent (no cycles).
    nd.left = index(nodes(i, 1), nd.hyperplane < 0 ? -1 : i + 1, nn - 1, "tree_nodes left");
    nd.right = index(nodes(i, 2), nd.hyperplane < 0 ? -1 : i + 1, nn - 1, "tree_nodes right");
    nd.leaf_begin = index(nodes(i, 3), 0, nl, "tree_nodes leaf_begin");
    nd.leaf_end = index(nodes(i, 4), nd.leaf_begin, nl, "tree_nodes leaf_end");
    law.tree.nodes.push_back(nd);
  }
  const Eigen::MatrixXd& ts = r.matrix("tree_stats", 1, 7);
  law.tree.stats = {static_cast<int>(ts(0)), static_cast<int>(ts(1)), static_cast<int>(ts(2)),
                    static_cast<int>(ts(3)), static_cast<int>(ts(4)), static_cast<int>(ts(5)), ts(6)};
  const Eigen::MatrixXd& bs = r.matrix("build_stats", 1, 11);
  MpQpStats& s = law.stats;
  s.complete = bs(0) != 0.0;
  s.seconds = bs(1);
  s.qp_solves = static_cast<int>(bs(2));
  s.lps = static_cast<int>(bs(3));
  s.lower_dimensional = static_cast<int>(bs(4));
  s.licq_reduced = static_cast<int>(bs(5));
  s.perturbed = static_cast<int>(bs(6));
  s.unresolved_facets = static_cast<int>(bs(7));
  s.holes_found = static_cast<int>(bs(8));
  s.coverage_checked = static_cast<int>(bs(9));
  s.stop_reason = r.text("stop_reason");
  r.finish();
  if (law.domain.empty()) r.fail("record 'domain_lo': the domain is empty in dimension " + std::to_string(law.domain.first_empty_dimension()));
  if (law.nz % law.M != 0) r.fail("record 'nz' = " + std::to_string(law.nz) + " is not a multiple of M = " + std::to_string(law.M));
  return law;
}

void save_explicit(const ExplicitLaw& law, const std::string& path) { write_binary_file(path, serialize_explicit(law)); }

ExplicitLaw load_explicit(const std::string& path, const ControllerArtifact* a) {
  ExplicitLaw law = deserialize_explicit(read_binary_file(path), path);
  if (a != nullptr) {
    const std::uint32_t crc = artifact_checksum(*a);
    if (crc != law.artifact_crc) {
      throw RecordFileError(path + ": built for another controller artifact (artifact CRC-32 " +
                            std::to_string(law.artifact_crc) + ", this artifact's is " + std::to_string(crc) +
                            "); rebuild it with `tmpc explicit`");
    }
    if (a->n != law.n || a->m * law.M != law.nz) {
      throw RecordFileError(path + ": records 'n' = " + std::to_string(law.n) + " and 'nz' = " + std::to_string(law.nz) +
                            " disagree with the artifact (" + std::to_string(a->n) + " states, " + std::to_string(a->m) +
                            " inputs, M = " + std::to_string(law.M) + ")");
    }
    for (int i = 0; i < law.n; ++i) {
      if (law.domain.lo(i) < a->x_bar.lo(i) - 1e-9 || law.domain.hi(i) > a->x_bar.hi(i) + 1e-9) {
        throw RecordFileError(path + ": record 'domain_lo': dimension " + std::to_string(i) + " [" +
                              std::to_string(law.domain.lo(i)) + ", " + std::to_string(law.domain.hi(i)) +
                              "] leaves the artifact's tightened state set [" + std::to_string(a->x_bar.lo(i)) + ", " +
                              std::to_string(a->x_bar.hi(i)) + "]");
      }
    }
  }
  return law;
}

}  // namespace tmpc
