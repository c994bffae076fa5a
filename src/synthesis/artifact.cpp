// Controller artifact: binary writer and strict reader.
#include "tmpc/synthesis/artifact.hpp"

#include "tmpc/synthesis/design.hpp"

namespace tmpc {

namespace {
constexpr FileMagic kMagic = {'T', 'M', 'P', 'C', 'A', 'R', 'T', '\0'};
}  // namespace

MpcQpData ControllerArtifact::qp(bool offset_free) const {
  MpcQpData d = build_mpc_qp(A, B, Sigma_rho, Sigma_lambda, L, x_bar, u_bar, N, M);
  if (offset_free) {
    const DisturbanceTarget t = disturbance_target();
    make_offset_free(d, t.Tx, t.Tu);
  }
  return d;
}

DisturbanceTarget ControllerArtifact::disturbance_target() const {
  // Tracked errors x, y, z, psi and their integrals (states 20..23) at zero; the
  // angles, the swing of the load and the inputs take up the force.
  return steady_state_target(A, B, D, {kX, kY, kZ, kPsi, kNx, kNx + 1, kNx + 2, kNx + 3});
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
  RecordWriter p;
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

  return p.seal(kMagic, kArtifactVersion);
}

ControllerArtifact deserialize_artifact(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  RecordReader r(bytes, kMagic, kArtifactVersion, source, "controller artifact");
  auto mat = [&](const std::string& name, Eigen::Index rows, Eigen::Index cols) { return r.matrix(name, rows, cols); };
  auto integer = [&](const std::string& name, std::int64_t lo, std::int64_t hi) { return r.integer(name, lo, hi); };
  ControllerArtifact a;
  a.config_text = r.text("config");
  a.tube_gain = r.text("tube_gain");
  a.rpi_variant = r.text("rpi_variant");
  a.terminal_cost = r.text("terminal_cost");
  // Sizes first, bounded before anything is built from them.
  a.n = integer("n", 1, 1000);
  a.m = integer("m", 1, 100);
  a.N = integer("N", 1, kMaxHorizon);
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
  r.finish();
  check_artifact(a, source);
  return a;
}

void save_artifact(const ControllerArtifact& a, const std::string& path) { write_binary_file(path, serialize_artifact(a)); }

ControllerArtifact load_artifact(const std::string& path) { return deserialize_artifact(read_binary_file(path), path); }

}  // namespace tmpc
