// Controller artifact: binary writer and strict reader.
#include "tmpc/synthesis/artifact.hpp"

#include <array>
#include <cstring>
#include <fstream>
#include <map>
#include <set>

#include "tmpc/synthesis/design.hpp"

namespace tmpc {

namespace {

constexpr char kMagic[8] = {'T', 'M', 'P', 'C', 'A', 'R', 'T', '\0'};
constexpr std::size_t kHeader = 20;
enum Kind : std::uint8_t { kMatrix = 1, kText = 2, kInt = 3 };

class Writer {
 public:
  void u8(std::uint8_t v) { b_.push_back(v); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
  void f64(double v) {
    std::uint64_t u;
    std::memcpy(&u, &v, 8);
    u64(u);
  }
  void name(const std::string& s) {
    u16(static_cast<std::uint16_t>(s.size()));
    b_.insert(b_.end(), s.begin(), s.end());
  }
  void matrix(const std::string& n, const Eigen::MatrixXd& m) {
    name(n);
    u8(kMatrix);
    u32(static_cast<std::uint32_t>(m.rows()));
    u32(static_cast<std::uint32_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      for (Eigen::Index i = 0; i < m.rows(); ++i) f64(m(i, j));
    }
  }
  void text(const std::string& n, const std::string& t) {
    name(n);
    u8(kText);
    u64(t.size());
    b_.insert(b_.end(), t.begin(), t.end());
  }
  void integer(const std::string& n, std::int64_t v) {
    name(n);
    u8(kInt);
    u64(static_cast<std::uint64_t>(v));
  }
  std::vector<std::uint8_t>& bytes() { return b_; }

 private:
  void le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t> b_;
};

struct Record {
  Kind kind;
  Eigen::MatrixXd m;
  std::string text;
  std::int64_t value = 0;
};

class Reader {
 public:
  Reader(const std::uint8_t* p, std::size_t n, const std::string& src) : p_(p), n_(n), src_(src) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw ArtifactError(src_ + ": " + what + " (at byte " + std::to_string(pos_) + ")");
  }
  void need(std::size_t k) const {
    if (n_ - pos_ < k) fail("record runs past the end of the payload");
  }
  std::uint64_t le(int k) {
    need(static_cast<std::size_t>(k));
    std::uint64_t v = 0;
    for (int i = 0; i < k; ++i) v |= static_cast<std::uint64_t>(p_[pos_ + static_cast<std::size_t>(i)]) << (8 * i);
    pos_ += static_cast<std::size_t>(k);
    return v;
  }
  double f64() {
    const std::uint64_t u = le(8);
    double v;
    std::memcpy(&v, &u, 8);
    return v;
  }
  bool done() const { return pos_ == n_; }
  std::pair<std::string, Record> record() {
    const std::size_t len = le(2);
    need(len);
    std::string name(reinterpret_cast<const char*>(p_ + pos_), len);
    pos_ += len;
    Record r;
    const std::uint64_t kind = le(1);
    if (kind == kMatrix) {
      r.kind = kMatrix;
      const std::uint64_t rows = le(4), cols = le(4);
      if (rows > (1u << 24) || cols > (1u << 24) || rows * cols * 8 > n_ - pos_) fail("matrix '" + name + "' too large");
      r.m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
      for (Eigen::Index j = 0; j < r.m.cols(); ++j) {
        for (Eigen::Index i = 0; i < r.m.rows(); ++i) r.m(i, j) = f64();
      }
    } else if (kind == kText) {
      r.kind = kText;
      const std::uint64_t l = le(8);
      need(l);
      r.text.assign(reinterpret_cast<const char*>(p_ + pos_), l);
      pos_ += l;
    } else if (kind == kInt) {
      r.kind = kInt;
      r.value = static_cast<std::int64_t>(le(8));
    } else {
      fail("record '" + name + "' has unknown kind " + std::to_string(kind));
    }
    return {name, r};
  }

 private:
  const std::uint8_t* p_;
  std::size_t n_;
  std::size_t pos_ = 0;
  const std::string& src_;
};

}  // namespace

MpcQpData ControllerArtifact::qp() const {
  return build_mpc_qp(A, B, Sigma_rho, Sigma_lambda, L, x_bar, u_bar, N, M);
}

ControllerArtifact make_artifact(const ControllerDesign& d) {
  ControllerArtifact a;
  a.config_text = d.config_text;
  a.tube_gain = d.cfg.synthesis.tube_gain;
  a.rpi_variant = d.cfg.synthesis.rpi_variant;
  a.terminal_cost = d.cfg.synthesis.terminal_cost;
  a.sample_time = d.em.sample_time;
  a.n = kNa;
  a.m = kNu;
  a.N = d.qp.N;
  a.M = d.qp.M;
  a.N_x = d.em.N_x;
  a.N_u = d.em.N_u;
  a.A = d.em.A_n;
  a.B = d.em.B_n;
  a.D = d.em.D_n;
  for (const Mat24& v : d.em.A_n_vertices) a.A_vertices.push_back(v);
  a.K = d.K;
  a.K_lqr = d.K_lqr;
  a.P_lqr = d.P_lqr;
  a.L = d.L_terminal;
  a.Sigma_rho = d.Sigma_rho_n;
  a.Sigma_lambda = d.Sigma_lambda_n;
  a.X = d.X;
  a.U = d.U;
  a.x_bar = d.x_bar;
  a.u_bar = d.u_bar;
  a.Z = d.tube.Z;
  a.W = d.W;
  a.u_eq = d.em.equilibrium.u;
  a.angles_eq = d.em.equilibrium.angles;
  a.margin = d.margin;
  return a;
}

std::vector<std::uint8_t> serialize_artifact(const ControllerArtifact& a) {
  Writer p;
  p.text("config", a.config_text);
  p.text("tube_gain", a.tube_gain);
  p.text("rpi_variant", a.rpi_variant);
  p.text("terminal_cost", a.terminal_cost);
  p.integer("n", a.n);
  p.integer("m", a.m);
  p.integer("N", a.N);
  p.integer("M", a.M);
  p.matrix("sample_time", Eigen::MatrixXd::Constant(1, 1, a.sample_time));
  p.matrix("N_x", a.N_x);
  p.matrix("N_u", a.N_u);
  p.matrix("A", a.A);
  p.matrix("B", a.B);
  p.matrix("D", a.D);
  p.integer("vertices", static_cast<std::int64_t>(a.A_vertices.size()));
  for (std::size_t i = 0; i < a.A_vertices.size(); ++i) p.matrix("A_vertex_" + std::to_string(i), a.A_vertices[i]);
  p.matrix("K", a.K);
  p.matrix("K_lqr", a.K_lqr);
  p.matrix("P_lqr", a.P_lqr);
  p.matrix("L", a.L);
  p.matrix("Sigma_rho", a.Sigma_rho);
  p.matrix("Sigma_lambda", a.Sigma_lambda);
  for (const auto& [name, box] : {std::pair<std::string, const Box*>{"X", &a.X}, {"U", &a.U}, {"x_bar", &a.x_bar}, {"u_bar", &a.u_bar}}) {
    p.matrix(name + "_lo", box->lo);
    p.matrix(name + "_hi", box->hi);
  }
  p.matrix("Z_c", a.Z.c);
  p.matrix("Z_G", a.Z.G);
  p.matrix("W_c", a.W.c);
  p.matrix("W_G", a.W.G);
  p.matrix("u_eq", a.u_eq);
  p.matrix("angles_eq", a.angles_eq);
  p.matrix("margin", Eigen::MatrixXd::Constant(1, 1, a.margin));

  Writer f;
  for (char c : kMagic) f.u8(static_cast<std::uint8_t>(c));
  f.u32(kArtifactVersion);
  f.u64(p.bytes().size());
  auto& out = f.bytes();
  out.insert(out.end(), p.bytes().begin(), p.bytes().end());
  f.u32(crc32(out.data(), out.size()));
  return out;
}

ControllerArtifact deserialize_artifact(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  if (bytes.size() < kHeader + 4) {
    throw ArtifactError(source + ": truncated: " + std::to_string(bytes.size()) + " bytes, a controller artifact has at least " +
                        std::to_string(kHeader + 4));
  }
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) throw ArtifactError(source + ": not a tmpc controller artifact (bad magic)");
  std::uint32_t version = 0;
  for (int i = 0; i < 4; ++i) version |= static_cast<std::uint32_t>(bytes[8 + static_cast<std::size_t>(i)]) << (8 * i);
  if (version != kArtifactVersion) {
    throw ArtifactError(source + ": format version " + std::to_string(version) + ", this build reads version " +
                        std::to_string(kArtifactVersion) + " (redesign with this tmpc)");
  }
  std::uint64_t payload = 0;
  for (int i = 0; i < 8; ++i) payload |= static_cast<std::uint64_t>(bytes[12 + static_cast<std::size_t>(i)]) << (8 * i);
  if (payload > bytes.size() || kHeader + payload + 4 != bytes.size()) {
    throw ArtifactError(source + ": size mismatch: the header announces " + std::to_string(payload) + " payload bytes, the file has " +
                        std::to_string(bytes.size()) + " bytes in all (truncated or extended)");
  }
  std::uint32_t stored = 0;
  for (int i = 0; i < 4; ++i) stored |= static_cast<std::uint32_t>(bytes[kHeader + payload + static_cast<std::size_t>(i)]) << (8 * i);
  if (crc32(bytes.data(), kHeader + payload) != stored) throw ArtifactError(source + ": checksum mismatch (the file is corrupt)");

  std::map<std::string, Record> recs;
  Reader r(bytes.data() + kHeader, payload, source);
  while (!r.done()) {
    auto [name, rec] = r.record();
    if (!recs.emplace(name, std::move(rec)).second) r.fail("duplicate record '" + name + "'");
  }
  std::set<std::string> used;
  auto get = [&](const std::string& name, Kind kind) -> const Record& {
    auto it = recs.find(name);
    if (it == recs.end()) throw ArtifactError(source + ": missing record '" + name + "'");
    if (it->second.kind != kind) throw ArtifactError(source + ": record '" + name + "' has the wrong kind");
    used.insert(name);
    return it->second;
  };
  auto mat = [&](const std::string& name, Eigen::Index rows, Eigen::Index cols) {
    const Record& rec = get(name, kMatrix);
    if (rec.m.rows() != rows || (cols >= 0 && rec.m.cols() != cols)) {
      throw ArtifactError(source + ": record '" + name + "' is " + std::to_string(rec.m.rows()) + "x" +
                          std::to_string(rec.m.cols()) + ", expected " + std::to_string(rows) + "x" +
                          (cols >= 0 ? std::to_string(cols) : std::string("any")));
    }
    if (!rec.m.allFinite()) throw ArtifactError(source + ": record '" + name + "' holds non-finite values");
    return rec.m;
  };
  auto integer = [&](const std::string& name, std::int64_t lo, std::int64_t hi) {
    const std::int64_t v = get(name, kInt).value;
    if (v < lo || v > hi) throw ArtifactError(source + ": record '" + name + "' = " + std::to_string(v) + " out of range");
    return static_cast<int>(v);
  };
  ControllerArtifact a;
  a.config_text = get("config", kText).text;
  a.tube_gain = get("tube_gain", kText).text;
  a.rpi_variant = get("rpi_variant", kText).text;
  a.terminal_cost = get("terminal_cost", kText).text;
  a.n = integer("n", 1, 10000);
  a.m = integer("m", 1, 10000);
  a.N = integer("N", 1, 100000);
  a.M = integer("M", 1, a.N);
  const int n = a.n, m = a.m;
  a.sample_time = mat("sample_time", 1, 1)(0, 0);
  a.N_x = mat("N_x", n, 1);
  a.N_u = mat("N_u", m, 1);
  a.A = mat("A", n, n);
  a.B = mat("B", n, m);
  a.D = mat("D", n, -1);
  const int nv = integer("vertices", 0, 1 << 16);
  for (int i = 0; i < nv; ++i) a.A_vertices.push_back(mat("A_vertex_" + std::to_string(i), n, n));
  a.K = mat("K", m, n);
  a.K_lqr = mat("K_lqr", m, n);
  a.P_lqr = mat("P_lqr", n, n);
  a.L = mat("L", n, n);
  a.Sigma_rho = mat("Sigma_rho", n, n);
  a.Sigma_lambda = mat("Sigma_lambda", m, m);
  a.X = Box(mat("X_lo", n, 1), mat("X_hi", n, 1));
  a.U = Box(mat("U_lo", m, 1), mat("U_hi", m, 1));
  a.x_bar = Box(mat("x_bar_lo", n, 1), mat("x_bar_hi", n, 1));
  a.u_bar = Box(mat("u_bar_lo", m, 1), mat("u_bar_hi", m, 1));
  a.Z = Zonotope(mat("Z_c", n, 1), mat("Z_G", n, -1));
  a.W = Zonotope(mat("W_c", n, 1), mat("W_G", n, -1));
  a.u_eq = mat("u_eq", 4, 1);
  a.angles_eq = mat("angles_eq", 4, 1);
  a.margin = mat("margin", 1, 1)(0, 0);
  for (const auto& kv : recs) {
    if (used.count(kv.first) == 0) throw ArtifactError(source + ": unknown record '" + kv.first + "'");
  }
  if (!(a.sample_time > 0.0)) throw ArtifactError(source + ": sample_time must be positive");
  if (a.x_bar.empty() || a.u_bar.empty()) throw ArtifactError(source + ": a tightened set is empty");
  return a;
}

void save_artifact(const ControllerArtifact& a, const std::string& path) {
  const std::vector<std::uint8_t> bytes = serialize_artifact(a);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw ArtifactError(path + ": cannot open for writing");
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw ArtifactError(path + ": write failed");
}

ControllerArtifact load_artifact(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ArtifactError(path + ": cannot open the file");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return deserialize_artifact(bytes, path);
}

}  // namespace tmpc
