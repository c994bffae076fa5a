// Controller artifact: binary writer and strict reader (format in artifact.hpp).
#include "tmpc/synthesis/artifact.hpp"

#include <cmath>
#include <sstream>

#include "tmpc/model/kinematic_tree.hpp"
#include "tmpc/qp/redundant_rows.hpp"
#include "tmpc/synthesis/design.hpp"

namespace tmpc {

namespace {
constexpr FileMagic kMagic = {'T', 'M', 'P', 'C', 'A', 'R', 'T', '\0'};

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : "\n") + x;
  return s;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

Eigen::MatrixXd scalar(double v) { return Eigen::MatrixXd::Constant(1, 1, v); }

Eigen::VectorXd indices(const std::vector<int>& v) {
  Eigen::VectorXd m(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) m(static_cast<Eigen::Index>(i)) = v[i];
  return m;
}

void write_vehicle(RecordWriter& w, const VehicleParams& p) {
  w.matrix("vehicle_scalars", (Eigen::VectorXd(9) << p.gravity, p.load_mass, p.rod_length, p.body_mass, p.rotor_mass,
                               p.dihedral, p.drag_torque_ratio, p.spin_right, p.spin_left)
                                  .finished());
  w.integer("vehicle_rotor_inertia_about_pivot", p.rotor_inertia_reference == RotorInertiaReference::Pivot ? 1 : 0);
  w.matrix("vehicle_load_inertia", p.load_inertia);
  w.matrix("vehicle_body_inertia", p.body_inertia);
  w.matrix("vehicle_rotor_inertia", p.rotor_inertia);
  Eigen::MatrixXd vectors(3, 5);
  vectors << p.d_a1b, p.d_b1, p.rotor_com, p.d_b_right, p.d_b_left;
  w.matrix("vehicle_vectors", vectors);
  w.matrix("vehicle_friction", Eigen::Map<const Eigen::VectorXd>(p.friction.data(), kNq));
}

VehicleParams read_vehicle(RecordReader& r) {
  VehicleParams p;
  const Eigen::MatrixXd& s = r.matrix("vehicle_scalars", 9, 1);
  p.gravity = s(0);
  p.load_mass = s(1);
  p.rod_length = s(2);
  p.body_mass = s(3);
  p.rotor_mass = s(4);
  p.dihedral = s(5);
  p.drag_torque_ratio = s(6);
  p.spin_right = s(7);
  p.spin_left = s(8);
  p.rotor_inertia_reference =
      r.integer("vehicle_rotor_inertia_about_pivot", 0, 1) == 1 ? RotorInertiaReference::Pivot : RotorInertiaReference::Com;
  p.load_inertia = r.matrix("vehicle_load_inertia", 3, 3);
  p.body_inertia = r.matrix("vehicle_body_inertia", 3, 3);
  p.rotor_inertia = r.matrix("vehicle_rotor_inertia", 3, 3);
  const Eigen::MatrixXd& v = r.matrix("vehicle_vectors", 3, 5);
  p.d_a1b = v.col(0);
  p.d_b1 = v.col(1);
  p.rotor_com = v.col(2);
  p.d_b_right = v.col(3);
  p.d_b_left = v.col(4);
  const Eigen::MatrixXd& f = r.matrix("vehicle_friction", kNq, 1);
  for (int i = 0; i < kNq; ++i) p.friction[static_cast<std::size_t>(i)] = f(i);
  return p;
}

void write_link(RecordWriter& w, const LinkSettings& l) {
  w.integer("link_watchdog_periods", l.watchdog_periods);
  w.integer("link_gate_horizon", l.gate_horizon);
  w.integer("link_resync_frames", l.resync_frames);
  w.integer("link_session_confirm", l.session_confirm);
  w.integer("link_sequence_window", l.sequence_window);
  w.matrix("link_numbers", (Eigen::VectorXd(12) << l.plant_hold_s, l.bound_position, l.bound_angle, l.bound_yaw,
                            l.bound_velocity, l.bound_rate, l.bound_time, l.jump_position, l.jump_angle, l.jump_velocity,
                            l.jump_rate, l.time_tolerance)
                               .finished());
}

LinkSettings read_link(RecordReader& r) {
  LinkSettings l;
  l.watchdog_periods = r.integer("link_watchdog_periods", 1, 100000);
  l.gate_horizon = r.integer("link_gate_horizon", 1, 100000);
  l.resync_frames = r.integer("link_resync_frames", 2, 1000);
  l.session_confirm = r.integer("link_session_confirm", 1, 1000);
  l.sequence_window = r.integer("link_sequence_window", 1, 1 << 29);
  const Eigen::MatrixXd& v = r.matrix("link_numbers", 12, 1);
  l.plant_hold_s = v(0);
  l.bound_position = v(1);
  l.bound_angle = v(2);
  l.bound_yaw = v(3);
  l.bound_velocity = v(4);
  l.bound_rate = v(5);
  l.bound_time = v(6);
  l.jump_position = v(7);
  l.jump_angle = v(8);
  l.jump_velocity = v(9);
  l.jump_rate = v(10);
  l.time_tolerance = v(11);
  return l;
}

}  // namespace

MpcQpData ControllerArtifact::qp(bool offset_free, bool soft) const {
  MpcQpData d = build_mpc_qp(A, B, Sigma_rho, Sigma_lambda, L, x_bar, u_bar, N, M);
  if (offset_free) {
    const DisturbanceTarget t = disturbance_target();
    make_offset_free(d, t.Tx, t.Tu);
  }
  if (rate_weighted()) add_input_rate_weight(d, Sigma_delta);
  if (soft) {
    if (!(soft_penalty > 0.0)) throw std::invalid_argument("the artifact has no soft-constraint penalty (soft_constraints off)");
    d.soft_penalty = soft_penalty;
  }
  const std::vector<int>& rows = offset_free ? redundant_rows_offset_free : redundant_rows;
  if (!rows.empty()) {
    d.redundant_rows = rows;
    d.domain = offset_free ? mpc_parameter_domain(d, certificate_d_max, certificate_c_max) : mpc_parameter_domain(d);
  }
  return d;
}

void ControllerArtifact::certify_redundant_rows() {
  redundant_rows.clear();
  redundant_rows_offset_free.clear();
  MpcQpData nominal = qp(false);
  redundant_rows = tmpc::certify_redundant_rows(nominal).rows;
  // The offset-free certificate's estimates: along each force axis, the largest force
  // whose steady state (x_s = Tx d, u_s = Tu d) fits the tightened sets; the residual
  // within W's interval hull.
  certificate_c_max = W.c.cwiseAbs() + W.G.cwiseAbs().rowwise().sum();
  certificate_d_max.setZero(D.cols());
  if (D.cols() == 0) return;  // no offset-free form
  const DisturbanceTarget t = disturbance_target();
  for (Eigen::Index j = 0; j < t.Tx.cols(); ++j) {
    double s = HUGE_VAL;
    auto fit = [&s](double coef, double lo, double hi) {
      if (coef != 0.0) s = std::min(s, std::min(std::abs(lo), std::abs(hi)) / std::abs(coef));
    };
    for (Eigen::Index i = 0; i < t.Tx.rows(); ++i) fit(t.Tx(i, j), x_bar.lo(i), x_bar.hi(i));
    for (Eigen::Index i = 0; i < t.Tu.rows(); ++i) fit(t.Tu(i, j), u_bar.lo(i), u_bar.hi(i));
    certificate_d_max(j) = std::isfinite(s) ? s : 0.0;
  }
  MpcQpData of = qp(true);
  redundant_rows_offset_free = tmpc::certify_redundant_rows(of, certificate_d_max, certificate_c_max).rows;
}

std::vector<int> ControllerArtifact::tracked_states() const {
  std::vector<int> s = integrated;
  for (int i = measured; i < n; ++i) s.push_back(i);
  return s;
}

std::vector<int> ControllerArtifact::velocity_rows() const {
  std::vector<int> rows;
  for (int i = 0; i < measured; ++i) {
    if (kinds[static_cast<std::size_t>(i)] == StateKind::Velocity) rows.push_back(i);
  }
  return rows;
}

DisturbanceTarget ControllerArtifact::disturbance_target() const {
  // Tracked errors and their integrals at zero; the other states and the inputs take
  // up the disturbance (tiltrotor: x, y, z, psi and the four integrals).
  return steady_state_target(A, B, D, tracked_states());
}

KalmanDesign kalman_model(const ControllerArtifact& a) {
  const int p = a.measured;
  KalmanDesign k = kalman_model(a.A.topLeftCorner(p, p), a.B.topRows(p), a.D.topRows(p), a.estimator_E_c, a.estimator_rows);
  k.L = a.estimator_L;
  k.P = a.estimator_P;
  k.Q = a.estimator_Q;
  k.R = a.estimator_noise.cwiseAbs2().asDiagonal();
  return k;
}

Eigen::MatrixXd estimation_error_map(const ControllerArtifact& a) {
  const KalmanDesign k = kalman_model(a);
  return (Eigen::MatrixXd::Identity(k.A_a.rows(), k.A_a.rows()) - k.L * k.C) * k.A_a;
}

ControllerArtifact make_artifact(const ControllerDesign& d) {
  ControllerArtifact a;
  const Config& c = d.cfg;
  a.config_text = d.config_text;
  a.tube_gain = c.synthesis.tube_gain;
  a.rpi_variant = c.synthesis.rpi_variant;
  a.terminal_cost = c.synthesis.terminal_cost;
  a.sample_time = d.em.sample_time;
  a.n = d.em.n;
  a.m = d.em.m;
  a.N = d.qp.N;
  a.M = d.qp.M;
  a.model = c.model;
  a.measured = d.em.measured;
  a.integrated = d.em.integrated;
  a.state_names = d.state_names;
  a.input_names = d.input_names;
  a.kinds = c.state_kinds();
  if (c.model == ModelKind::Tiltrotor) {
    a.vehicle = c.vehicle;
  } else {
    a.linear_A = c.linear.A;
    a.linear_B = c.linear.B;
    a.linear_D = c.linear.D;
  }
  a.attitude = c.attitude;
  a.substep = c.simulation.substep;
  a.input_min = c.input_min;
  a.input_max = c.input_max;
  a.envelope = d.envelope;
  a.feedforward_min = d.em.u_r_min;
  a.feedforward_max = d.em.u_r_max;
  a.solver = c.solver;
  a.tube_law = c.tube_law;
  a.link = c.link;
  a.N_x = d.em.N_x;
  a.N_u = d.em.N_u;
  a.A = d.em.A_n;
  a.B = d.em.B_n;
  a.D = d.em.D_n;
  a.A_vertices = d.em.A_n_vertices;
  a.K = d.K;
  a.K_lqr = d.K_lqr;
  a.P_lqr = d.P_lqr;
  a.L = d.L_terminal;
  a.Sigma_rho = d.Sigma_rho_n;
  a.Sigma_lambda = d.Sigma_lambda_n;
  a.Sigma_delta = d.Sigma_delta_n.size() > 0 ? d.Sigma_delta_n : Eigen::MatrixXd::Zero(a.m, a.m);
  a.X = d.X;
  a.U = d.U;
  a.x_bar = d.x_bar;
  a.u_bar = d.u_bar;
  a.Z = d.tube.Z;
  a.W = d.W;
  a.u_eq = c.model == ModelKind::Tiltrotor ? Eigen::VectorXd(d.em.equilibrium.u) : Eigen::VectorXd::Zero(a.m);
  a.angles_eq = c.model == ModelKind::Tiltrotor ? Eigen::VectorXd(d.em.equilibrium.angles) : Eigen::VectorXd::Zero(0);
  a.margin = d.margin;
  if (d.kalman) {
    a.estimator = "kalman";
    a.estimator_rows = d.kf.measured_rows;
    a.estimator_E_c = d.kf.E_c;
    a.estimator_L = d.kf.L;
    a.estimator_noise = d.kf.R.diagonal().cwiseSqrt();
    a.estimator_monitor << c.estimation.monitor_residual_below, c.estimation.monitor_filter_above, c.estimation.monitor_window_s;
    a.estimator_P = d.kf.P;
    a.estimator_Q = d.kf.Q;
    a.estimator_start << c.estimation.start_force, c.estimation.start_residual, c.estimation.start_state;
  }
  a.estimation_error_radius = Eigen::VectorXd::Zero(a.n);
  // The applied form's figures (the bounded form's when none is applied).
  const bool gaussian = c.estimation.gaussian_noise();
  if (d.of_computed) a.noise_margin = gaussian ? d.of.noise_margin_gaussian : d.of.noise_margin;
  if (d.output_feedback) a.estimation_error_radius = gaussian ? d.of.e_x_radius_gaussian : d.of.e_x_radius;
  a.soft_constraints = c.soft_constraints.enabled;
  a.soft_penalty = c.soft_constraints.enabled ? c.soft_constraints.penalty : 0.0;
  a.certify_redundant_rows();
  return a;
}

std::vector<std::uint8_t> serialize_artifact(const ControllerArtifact& a) {
  RecordWriter p;
  p.text("config", a.config_text);
  p.text("tube_gain", a.tube_gain);
  p.text("rpi_variant", a.rpi_variant);
  p.text("terminal_cost", a.terminal_cost);
  p.text("model", a.model == ModelKind::Tiltrotor ? "tiltrotor" : "linear");
  p.integer("n", a.n);
  p.integer("m", a.m);
  p.integer("N", a.N);
  p.integer("M", a.M);
  p.integer("measured", a.measured);
  p.matrix("integrated", indices(a.integrated));
  p.text("state_names", join(a.state_names));
  p.text("input_names", join(a.input_names));
  std::vector<int> kinds;
  for (StateKind k : a.kinds) kinds.push_back(static_cast<int>(k));
  p.matrix("state_kinds", indices(kinds));
  if (a.model == ModelKind::Tiltrotor) {
    write_vehicle(p, a.vehicle);
    p.integer("reference_attitude", a.attitude == ReferenceAttitude::Trim ? 0 : 1);
    p.matrix("envelope_acceleration_min", a.envelope.acceleration_min);
    p.matrix("envelope_acceleration_max", a.envelope.acceleration_max);
    p.matrix("envelope_numbers", (Eigen::VectorXd(4) << a.envelope.speed_max, a.envelope.yaw, a.envelope.yaw_tolerance,
                                   a.envelope.yaw_rate_max).finished());
    p.matrix("angles_eq", a.angles_eq);
  } else {
    p.matrix("linear_A", a.linear_A);
    p.matrix("linear_B", a.linear_B);
    p.matrix("linear_D", a.linear_D);
  }
  p.matrix("substep", scalar(a.substep));
  p.matrix("input_min", a.input_min);
  p.matrix("input_max", a.input_max);
  p.matrix("feedforward_min", a.feedforward_min);
  p.matrix("feedforward_max", a.feedforward_max);
  p.matrix("solver", (Eigen::VectorXd(2) << a.solver.admm_epsilon, a.solver.admm_eta).finished());
  p.integer("tube_law_offset_free", a.tube_law.offset_free ? 1 : 0);
  p.matrix("tube_law_observer_gain", scalar(a.tube_law.observer_gain));
  p.matrix("tube_law_revert", (Eigen::MatrixXd(2, 1) << a.tube_law.revert_beyond, a.tube_law.revert_within).finished());
  write_link(p, a.link);
  p.matrix("sample_time", scalar(a.sample_time));
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
  p.matrix("Sigma_delta", a.Sigma_delta.size() > 0 ? a.Sigma_delta : Eigen::MatrixXd::Zero(a.m, a.m));
  for (const auto& [name, box] : {std::pair<std::string, const Box*>{"X", &a.X}, {"U", &a.U}, {"x_bar", &a.x_bar}, {"u_bar", &a.u_bar}}) {
    p.matrix(name + "_lo", box->lo);
    p.matrix(name + "_hi", box->hi);
  }
  p.matrix("Z_c", a.Z.c);
  p.matrix("Z_G", a.Z.G);
  p.matrix("W_c", a.W.c);
  p.matrix("W_G", a.W.G);
  p.matrix("u_eq", a.u_eq);
  p.matrix("margin", scalar(a.margin));
  p.text("estimator", a.estimator);
  if (a.estimator == "kalman") {
    p.matrix("estimator_rows", indices(a.estimator_rows));
    p.matrix("estimator_E_c", a.estimator_E_c);
    p.matrix("estimator_L", a.estimator_L);
    p.matrix("estimator_noise", a.estimator_noise);
    p.matrix("estimator_monitor", a.estimator_monitor);
    p.matrix("estimator_P", a.estimator_P);
    p.matrix("estimator_Q", a.estimator_Q);
    p.matrix("estimator_start", a.estimator_start);
  }
  p.matrix("noise_margin", scalar(a.noise_margin));
  p.matrix("estimation_error_radius", a.estimation_error_radius);
  p.integer("soft_constraints", a.soft_constraints ? 1 : 0);
  p.matrix("soft_penalty", scalar(a.soft_penalty));
  p.matrix("redundant_rows", indices(a.redundant_rows));
  p.matrix("redundant_rows_offset_free", indices(a.redundant_rows_offset_free));
  p.matrix("certificate_d_max", a.certificate_d_max);
  p.matrix("certificate_c_max", a.certificate_c_max);
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
  const std::string model = r.text("model");
  if (model != "tiltrotor" && model != "linear") r.fail("record 'model' is '" + model + "' (expected tiltrotor or linear)");
  a.model = model == "tiltrotor" ? ModelKind::Tiltrotor : ModelKind::Linear;
  // Sizes first, bounded before anything is built from them.
  a.n = integer("n", 1, kMaxStates);
  a.m = integer("m", 1, kMaxInputs);
  a.N = integer("N", 1, kMaxHorizon);
  a.M = integer("M", 1, a.N);
  a.measured = integer("measured", 1, a.n);
  const int n = a.n, m = a.m, p = a.measured;
  const Eigen::MatrixXd& integ = mat("integrated", n - p, 1);
  for (Eigen::Index i = 0; i < integ.rows(); ++i) {
    const double v = integ(i);
    if (v != std::floor(v) || v < 0 || v >= p) r.fail("record 'integrated' entry " + std::to_string(i) + " is not a measured state");
    a.integrated.push_back(static_cast<int>(v));
  }
  a.state_names = split(r.text("state_names"));
  a.input_names = split(r.text("input_names"));
  if (static_cast<int>(a.state_names.size()) != n) r.fail("record 'state_names' has " + std::to_string(a.state_names.size()) + " names for " + std::to_string(n) + " states");
  if (static_cast<int>(a.input_names.size()) != m) r.fail("record 'input_names' has " + std::to_string(a.input_names.size()) + " names for " + std::to_string(m) + " inputs");
  const Eigen::MatrixXd& kinds = mat("state_kinds", n, 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double v = kinds(i);
    if (v != std::floor(v) || v < 0 || v > static_cast<double>(StateKind::Integral)) r.fail("record 'state_kinds' entry " + std::to_string(i) + " is not a state kind");
    a.kinds.push_back(static_cast<StateKind>(static_cast<int>(v)));
  }
  if (a.model == ModelKind::Tiltrotor) {
    a.vehicle = read_vehicle(r);
    a.attitude = integer("reference_attitude", 0, 1) == 0 ? ReferenceAttitude::Trim : ReferenceAttitude::Equilibrium;
    a.envelope.acceleration_min = mat("envelope_acceleration_min", 3, 1);
    a.envelope.acceleration_max = mat("envelope_acceleration_max", 3, 1);
    const Eigen::MatrixXd& e = mat("envelope_numbers", 4, 1);
    a.envelope.speed_max = e(0);
    a.envelope.yaw = e(1);
    a.envelope.yaw_tolerance = e(2);
    a.envelope.yaw_rate_max = e(3);  // < 0: the fixed yaw
    a.angles_eq = mat("angles_eq", 4, 1);
  } else {
    a.linear_A = mat("linear_A", p, p);
    a.linear_B = mat("linear_B", p, m);
    a.linear_D = mat("linear_D", p, -1);
  }
  a.substep = mat("substep", 1, 1)(0, 0);
  a.input_min = mat("input_min", m, 1);
  a.input_max = mat("input_max", m, 1);
  a.feedforward_min = mat("feedforward_min", m, 1);
  a.feedforward_max = mat("feedforward_max", m, 1);
  const Eigen::MatrixXd& so = mat("solver", 2, 1);
  a.solver.admm_epsilon = so(0);
  a.solver.admm_eta = so(1);
  a.tube_law.offset_free = integer("tube_law_offset_free", 0, 1) == 1;
  a.tube_law.observer_gain = mat("tube_law_observer_gain", 1, 1)(0, 0);
  const Eigen::MatrixXd& rv = mat("tube_law_revert", 2, 1);
  a.tube_law.revert_beyond = rv(0);
  a.tube_law.revert_within = rv(1);
  a.link = read_link(r);
  a.sample_time = mat("sample_time", 1, 1)(0, 0);
  a.N_x = mat("N_x", n, 1);
  a.N_u = mat("N_u", m, 1);
  a.A = mat("A", n, n);
  a.B = mat("B", n, m);
  a.D = mat("D", n, -1);
  const int nv = integer("vertices", 0, 64);
  for (int i = 0; i < nv; ++i) a.A_vertices.push_back(mat("A_vertex_" + std::to_string(i), n, n));
  a.K = mat("K", m, n);
  a.K_lqr = mat("K_lqr", m, n);
  a.P_lqr = mat("P_lqr", n, n);
  a.L = mat("L", n, n);
  a.Sigma_rho = mat("Sigma_rho", n, n);
  a.Sigma_lambda = mat("Sigma_lambda", m, m);
  a.Sigma_delta = mat("Sigma_delta", m, m);
  a.X = Box(mat("X_lo", n, 1), mat("X_hi", n, 1));
  a.U = Box(mat("U_lo", m, 1), mat("U_hi", m, 1));
  a.x_bar = Box(mat("x_bar_lo", n, 1), mat("x_bar_hi", n, 1));
  a.u_bar = Box(mat("u_bar_lo", m, 1), mat("u_bar_hi", m, 1));
  a.Z = Zonotope(mat("Z_c", n, 1), mat("Z_G", n, -1));
  a.W = Zonotope(mat("W_c", n, 1), mat("W_G", n, -1));
  a.u_eq = mat("u_eq", m, 1);
  a.margin = mat("margin", 1, 1)(0, 0);
  a.estimator = r.text("estimator");
  if (a.estimator != "residual" && a.estimator != "kalman") r.fail("record 'estimator' is '" + a.estimator + "' (expected residual or kalman)");
  if (a.estimator == "kalman") {
    const Eigen::MatrixXd& rows = mat("estimator_rows", -1, 1);
    if (rows.rows() < 1 || rows.rows() > p) r.fail("record 'estimator_rows' has " + std::to_string(rows.rows()) + " rows for " + std::to_string(p) + " measured states");
    for (Eigen::Index i = 0; i < rows.rows(); ++i) {
      const double v = rows(i);
      if (v != std::floor(v) || v < 0 || v >= p) r.fail("record 'estimator_rows' entry " + std::to_string(i) + " is not a measured state");
      a.estimator_rows.push_back(static_cast<int>(v));
    }
    a.estimator_E_c = mat("estimator_E_c", p, -1);
    a.estimator_L = mat("estimator_L", p + a.D.cols() + a.estimator_E_c.cols(), static_cast<Eigen::Index>(a.estimator_rows.size()));
    a.estimator_noise = mat("estimator_noise", static_cast<Eigen::Index>(a.estimator_rows.size()), 1);
    a.estimator_monitor = mat("estimator_monitor", 3, 1);
    a.estimator_P = mat("estimator_P", a.estimator_L.rows(), a.estimator_L.rows());
    a.estimator_Q = mat("estimator_Q", a.estimator_L.rows(), a.estimator_L.rows());
    a.estimator_start = mat("estimator_start", 3, 1);
  }
  a.noise_margin = mat("noise_margin", 1, 1)(0, 0);
  a.estimation_error_radius = mat("estimation_error_radius", n, 1);
  a.soft_constraints = integer("soft_constraints", 0, 1) == 1;
  a.soft_penalty = mat("soft_penalty", 1, 1)(0, 0);
  const int rows = a.M * m + a.N * n;
  for (const auto& [name, list] : {std::pair<std::string, std::vector<int>*>{"redundant_rows", &a.redundant_rows},
                                   {"redundant_rows_offset_free", &a.redundant_rows_offset_free}}) {
    const Eigen::MatrixXd& v = mat(name, -1, 1);
    for (Eigen::Index i = 0; i < v.rows(); ++i) {
      const double x = v(i);
      if (x != std::floor(x) || x < 0 || x >= rows || (i > 0 && x <= v(i - 1))) {
        r.fail("record '" + name + "' entry " + std::to_string(i) + " is not an increasing index of a QP row");
      }
      list->push_back(static_cast<int>(x));
    }
  }
  a.certificate_d_max = mat("certificate_d_max", a.D.cols(), 1);
  a.certificate_c_max = mat("certificate_c_max", n, 1);
  r.finish();
  check_artifact(a, source);
  return a;
}

void save_artifact(const ControllerArtifact& a, const std::string& path) { write_binary_file(path, serialize_artifact(a)); }

ControllerArtifact load_artifact(const std::string& path) { return deserialize_artifact(read_binary_file(path), path); }

}  // namespace tmpc
