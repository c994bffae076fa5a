// YAML loading and validation of the design configuration.
#include "tmpc/model/config.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <algorithm>
#include <set>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <yaml-cpp/yaml.h>

#include "trajectory_yaml.hpp"
#include "yaml_section.hpp"

#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {

namespace {

using detail::Section;
using detail::vec3;


/// 3x3 inertia: symmetric, positive definite, triangle inequality checked by the
/// caller where the body must be physical.
Eigen::Matrix3d inertia(Section& s, const std::string& k) {
  const auto v = s.vector(k, 9);
  Eigen::Matrix3d m;
  m << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-12 * m.cwiseAbs().maxCoeff()) {
    s.fail(s.key(k), "inertia must be symmetric");
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
  if (es.eigenvalues().minCoeff() <= 0.0) s.fail(s.key(k), "inertia must be positive definite");
  return m;
}

/// A rigid body's principal moments satisfy the triangle inequality I1 + I2 >= I3
/// (each is a sum of two of the three second moments of the mass distribution).
void require_physical_inertia(Section& s, const std::string& k, const Eigen::Matrix3d& m, const std::string& about = "") {
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m).eigenvalues();  // ascending
  if (ev(0) <= 0.0) s.fail(s.key(k), "inertia" + about + " must be positive definite");
  if (ev(0) + ev(1) < ev(2) * (1.0 - 1e-9)) {
    std::ostringstream os;
    os << "not the inertia of a rigid body" << about << ": principal moments " << ev(0) << ", " << ev(1) << ", "
       << ev(2) << " kg m^2 violate the triangle inequality (" << ev(0) << " + " << ev(1) << " < " << ev(2) << ")";
    s.fail(s.key(k), os.str());
  }
}

double sign(Section& s, const std::string& k) {
  const double v = s.number(k);
  if (v != 1.0 && v != -1.0) s.fail(s.key(k), "must be +1 or -1");
  return v;
}

void load_vehicle(Section v, VehicleParams& p) {
  p.gravity = v.positive("gravity");
  {
    Section s = v.section("load");
    p.load_mass = s.positive("mass");
    p.load_inertia = inertia(s, "inertia");
    require_physical_inertia(s, "inertia", p.load_inertia);
    s.finish();
  }
  p.rod_length = v.positive("rod_length");
  {
    Section s = v.section("body");
    p.body_mass = s.positive("mass");
    p.body_inertia = inertia(s, "inertia");
    require_physical_inertia(s, "inertia", p.body_inertia);
    p.d_a1b = vec3(s, "rod_to_origin");
    p.d_b1 = vec3(s, "com");
    s.finish();
  }
  {
    Section s = v.section("rotor");
    p.rotor_mass = s.positive("mass");
    p.rotor_inertia = inertia(s, "inertia");
    const std::string ref = s.text("inertia_about", {"com", "pivot"});
    p.rotor_inertia_reference = ref == "com" ? RotorInertiaReference::Com : RotorInertiaReference::Pivot;
    p.rotor_com = vec3(s, "com");
    p.d_b_right = vec3(s, "pivot_right");
    p.d_b_left = vec3(s, "pivot_left");
    p.dihedral = s.number_in("dihedral", -0.5, 0.5);
    p.drag_torque_ratio = s.number_in("drag_torque_ratio", 0.0, 1.0);
    p.spin_right = sign(s, "spin_right");
    p.spin_left = sign(s, "spin_left");
    if (p.rotor_inertia_reference == RotorInertiaReference::Pivot) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(p.rotor_inertia_about_com());
      if (es.eigenvalues().minCoeff() <= 0.0) {
        s.fail(s.key("inertia"), "inertia about the pivot leaves a non-positive CoM inertia");
      }
      // Set S2 (about the pivot) is not a rigid body's inertia by construction (model
      // spec 7.1): it is kept selectable for Rego's linear model, so only the CoM
      // inertia it implies must be positive definite.
    } else {
      require_physical_inertia(s, "inertia", p.rotor_inertia);
    }
    s.finish();
  }
  const auto fr = v.vector("friction", 10);
  for (std::size_t i = 0; i < 10; ++i) {
    if (fr[i] < 0.0) v.fail(v.key("friction") + "[" + std::to_string(i) + "]", "must be >= 0");
    p.friction[i] = fr[i];
  }
  v.finish();
}

Eigen::VectorXd to_eigen(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

void load_linear(Section s, LinearModelSpec& l) {
  l.A = s.matrix("A", -1, -1);
  const long n = l.A.rows();
  if (l.A.cols() != n) s.fail(s.key("A"), "must be square (" + std::to_string(n) + "x" + std::to_string(l.A.cols()) + ")");
  if (n > 40) s.fail(s.key("A"), "at most 40 states (the serial frame carries 48 values)");
  l.B = s.matrix("B", n, -1);
  l.D = s.has("D") ? s.matrix("D", n, -1) : Eigen::MatrixXd::Zero(n, 1);
  for (Section st : s.sections("states")) {
    l.state_names.push_back(st.string("name"));
    try {
      l.kinds.push_back(state_kind_from_string(st.string("kind")));
    } catch (const std::invalid_argument& e) {
      st.fail(st.key("kind"), e.what());
    }
    if (l.kinds.back() == StateKind::Integral) st.fail(st.key("kind"), "integral states are made by `integrate`, not listed");
    st.finish();
  }
  if (static_cast<long>(l.state_names.size()) != n) {
    s.fail(s.key("states"), "expected " + std::to_string(n) + " states (A is " + std::to_string(n) + "x" +
                                std::to_string(n) + "), got " + std::to_string(l.state_names.size()));
  }
  l.input_names = s.strings("inputs");
  if (static_cast<long>(l.input_names.size()) != l.B.cols()) {
    s.fail(s.key("inputs"), "expected " + std::to_string(l.B.cols()) + " names (B has " + std::to_string(l.B.cols()) +
                                " columns), got " + std::to_string(l.input_names.size()));
  }
  for (const std::string& name : s.has("integrate") ? s.strings("integrate") : std::vector<std::string>{}) {
    const auto it = std::find(l.state_names.begin(), l.state_names.end(), name);
    if (it == l.state_names.end()) s.fail(s.key("integrate"), "no state named '" + name + "'");
    l.integrated.push_back(static_cast<int>(it - l.state_names.begin()));
  }
  s.finish();
}

Config parse(const YAML::Node& root_node, const std::string& source) {
  Config c;
  c.source = source;
  Section root(root_node, "", c.source);

  c.model = root.has("model") && root.text("model", {"tiltrotor", "linear"}) == "linear" ? ModelKind::Linear
                                                                                         : ModelKind::Tiltrotor;
  if (c.model == ModelKind::Tiltrotor) {
    load_vehicle(root.section("vehicle"), c.vehicle);
  } else {
    load_linear(root.section("linear"), c.linear);
  }
  const int n = c.states(), m = c.inputs(), p = c.measured();

  if (root.has("reference")) {
    Section s = root.section("reference");
    c.attitude = s.text("attitude", {"trim", "equilibrium"}) == "trim" ? ReferenceAttitude::Trim
                                                                     : ReferenceAttitude::Equilibrium;
    s.finish();
  }

  if (c.model == ModelKind::Tiltrotor) {
    Section s = root.section("envelope");
    EnvelopeSettings& e = c.envelope;
    e.yaw = s.number_in("yaw", -M_PI, M_PI);
    // Either a fixed yaw (yaw_tolerance) or any yaw at a bounded rate (yaw_rate_max).
    if (s.has("yaw_rate_max")) {
      if (s.has("yaw_tolerance")) {
        s.fail(s.key("yaw_tolerance"), "give yaw_tolerance (a fixed-yaw design) or yaw_rate_max (any yaw), not both");
      }
      e.yaw_rate_max = s.number_in("yaw_rate_max", 0.0, 10.0);
    } else {
      e.yaw_tolerance = s.number_in("yaw_tolerance", 0.0, M_PI);
    }
    const bool from = s.has("trajectories");
    if (from) {
      e.trajectories = s.strings("trajectories");
      if (e.trajectories.empty()) s.fail(s.key("trajectories"), "expected at least one scenario file");
      if (s.has("margin")) e.margin = s.number_in("margin", 0.0, 10.0);
    }
    if (!from || s.has("acceleration_min")) {
      e.acceleration_min = vec3(s, "acceleration_min");
      e.acceleration_max = vec3(s, "acceleration_max");
      for (int i = 0; i < 3; ++i) {
        if (!(e.acceleration_max(i) >= e.acceleration_min(i))) {
          s.fail(s.key("acceleration_max") + "[" + std::to_string(i) + "]", "must be >= acceleration_min");
        }
        if (std::abs(e.acceleration_min(i)) > 50.0 || std::abs(e.acceleration_max(i)) > 50.0) {
          s.fail(s.key("acceleration_max") + "[" + std::to_string(i) + "]", "beyond 50 m/s^2: not a flight envelope");
        }
      }
      e.speed_max = s.number_in("speed_max", 0.0, 100.0);
    }
    s.finish();
  }

  c.sample_time = root.number_in("sample_time", 1e-5, 1.0);

  {
    Section s = root.section("constraints");
    c.input_min = to_eigen(s.vector("input_min", static_cast<std::size_t>(m)));
    c.input_max = to_eigen(s.vector("input_max", static_cast<std::size_t>(m)));
    for (int i = 0; i < m; ++i) {
      if (!(c.input_max[i] > c.input_min[i])) {
        s.fail(s.key("input_max") + "[" + std::to_string(i) + "]", "must exceed input_min");
      }
    }
    if (c.model == ModelKind::Tiltrotor && (c.input_min[0] < 0.0 || c.input_min[1] < 0.0)) {
      s.fail(s.key("input_min"), "thrusts cannot be negative");
    }
    c.state_error_max = to_eigen(s.vector("state_error_max", static_cast<std::size_t>(n)));
    for (int i = 0; i < n; ++i) {
      if (!(c.state_error_max[i] > 0.0)) {
        s.fail(s.key("state_error_max") + "[" + std::to_string(i) + "]", "half-width must be positive");
      }
    }
    s.finish();
  }

  {
    Section s = root.section("weights");
    c.input_weights = to_eigen(s.vector("input", static_cast<std::size_t>(m)));
    c.state_weights = to_eigen(s.vector("state", static_cast<std::size_t>(n)));
    for (int i = 0; i < m; ++i) {
      if (!(c.input_weights[i] > 0.0)) {
        s.fail(s.key("input") + "[" + std::to_string(i) + "]", "weight must be positive");
      }
    }
    for (int i = 0; i < n; ++i) {
      if (!(c.state_weights[i] > 0.0)) {
        s.fail(s.key("state") + "[" + std::to_string(i) + "]", "weight must be positive");
      }
    }
    c.input_rate_weights = Eigen::VectorXd::Zero(m);
    if (s.has("input_rate")) {
      c.input_rate_weights = to_eigen(s.vector("input_rate", static_cast<std::size_t>(m)));
      for (int i = 0; i < m; ++i) {
        if (!(c.input_rate_weights[i] >= 0.0) || !std::isfinite(c.input_rate_weights[i])) {
          s.fail(s.key("input_rate") + "[" + std::to_string(i) + "]", "weight must be finite and >= 0");
        }
      }
    }
    s.finish();
  }

  {
    Section s = root.section("simulation");
    c.simulation.substep = s.number_in("substep", 1e-6, 0.1);
    s.finish();
    const double ratio = c.sample_time / c.simulation.substep;
    if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio) {
      s.fail(s.key("substep"), "must divide sample_time into a whole number of steps");
    }
  }

  {
    Section s = root.section("error_model");
    const std::string d = s.text("discretization", {"zoh", "euler"});
    c.error_model.discretization = d == "zoh" ? Discretization::Zoh : Discretization::Euler;
    c.error_model.envelope_grid = s.has("envelope_grid") ? s.integer_in("envelope_grid", 2, 21) : 5;
    s.finish();
  }

  {
    Section s = root.section("solver");
    c.solver.admm_epsilon = s.number_in("admm_epsilon", 1e-12, 1.0);
    c.solver.admm_eta = s.number_in("admm_eta", 1e-6, 1.0 - 1e-12);
    s.finish();
  }

  if (root.has("tube_law")) {
    Section s = root.section("tube_law");
    c.tube_law.offset_free = s.flag("offset_free");
    c.tube_law.observer_gain = s.number_in("observer_gain", 1e-6, 1.0);
    if (s.has("revert_beyond")) c.tube_law.revert_beyond = s.number_in("revert_beyond", 0.0, 1e6);
    if (s.has("revert_within")) c.tube_law.revert_within = s.number_in("revert_within", 1.0, 1e6);
    if (!c.tube_law.revert_beyond_valid()) {
      s.fail(s.key("revert_beyond"), "must be 0 (off) or above 1 (times the state bounds), got " +
                                         std::to_string(c.tube_law.revert_beyond));
    }
    if (!c.tube_law.revert_within_valid()) {  // revert_within >= 1 above: it exceeds revert_beyond
      s.fail(s.key("revert_within"), "is above revert_beyond (" + std::to_string(c.tube_law.revert_beyond) + ")");
    }
    s.finish();
  }

  if (root.has("estimation")) {
    Section s = root.section("estimation");
    EstimationSettings& e = c.estimation;
    e.observer = s.text("observer", {"residual", "kalman"});
    e.measured = s.text("measured", {"all", "positions_angles_rates"});
    {
      Section n = s.section("measurement_noise");
      const char* groups[] = {"position", "angle", "velocity", "angular_rate"};
      for (std::size_t g = 0; g < 4; ++g) e.noise[g] = n.positive(groups[g]);
      n.finish();
    }
    {
      Section q = s.section("process_noise");
      e.process_state_fraction = q.positive("state_fraction");
      e.process_force = q.positive("force");
      e.process_residual = q.positive("residual");
      q.finish();
    }
    if (s.has("start_prior")) {
      Section q = s.section("start_prior");
      e.start_force = q.number_in("force", 0.0, 1e4);
      if (q.has("residual")) e.start_residual = q.number_in("residual", 0.0, 1e3);
      if (q.has("state")) e.start_state = q.number_in("state", 0.0, 1e3);
      q.finish();
    }
    e.output_feedback_tube = s.has("output_feedback_tube") && s.flag("output_feedback_tube");
    if (s.has("output_feedback_noise")) e.output_feedback_noise = s.text("output_feedback_noise", {"bounded", "gaussian"});
    if (s.has("noise_bound_sigmas")) e.noise_bound_sigmas = s.number_in("noise_bound_sigmas", 0.5, 10.0);
    if (s.has("force_rate_bound")) e.force_rate_bound = s.number_in("force_rate_bound", 0.0, 1e3);
    if (s.has("residual_rate_bound")) e.residual_rate_bound = s.number_in("residual_rate_bound", 0.0, 1.0);
    if (s.has("noise_monitor") && s.raw("noise_monitor").IsScalar()) {
      // `noise_monitor: off` (a configuration based on one with a monitor): the filter alone.
      s.text("noise_monitor", {"off"});
      e.monitor_residual_below = e.monitor_filter_above = 0.0;
    } else if (s.has("noise_monitor")) {
      Section m = s.section("noise_monitor");
      e.monitor_residual_below = m.number_in("residual_below", 1e-6, 1.0);
      e.monitor_filter_above = m.number_in("filter_above", e.monitor_residual_below, 1.0);
      if (m.has("window")) e.monitor_window_s = m.number_in("window", 0.01, 60.0);
      m.finish();
    }
    s.finish();
    if (e.observer == "kalman" && !c.tube_law.offset_free) {
      s.fail(s.key("observer"), "the Kalman filter estimates the offset-free law's disturbance: needs tube_law.offset_free: true");
    }
    if (e.observer != "kalman" && e.monitor_residual_below > 0.0) {
      s.fail(s.key("noise_monitor"), "switches between the Kalman filter and the residual observer: needs observer: kalman");
    }
  }

  if (root.has("soft_constraints")) {
    Section s = root.section("soft_constraints");
    c.soft_constraints.enabled = s.flag("enabled");
    if (s.has("penalty")) c.soft_constraints.penalty = s.number_in("penalty", 0.0, 1e12);
    if (s.has("safety_factor")) c.soft_constraints.safety_factor = s.number_in("safety_factor", 1.0, 1e6);
    s.finish();
  }

  {
    Section s = root.section("synthesis");
    SynthesisSettings& y = c.synthesis;
    y.tube_gain = s.text("tube_gain", {"lqr", "lmi_thesis", "lmi_robust"});
    y.compare_gains = s.flag("compare_gains");
    y.lqr_input_scale = Eigen::VectorXd::Ones(c.inputs());
    if (s.has("lqr_input_scale")) {
      const std::vector<double> v = s.vector("lqr_input_scale", static_cast<std::size_t>(c.inputs()));
      for (std::size_t i = 0; i < v.size(); ++i) {
        if (!(v[i] > 0.0)) s.fail(s.key("lqr_input_scale"), "entries must be positive");
        y.lqr_input_scale(static_cast<Eigen::Index>(i)) = v[i];
      }
    }
    {
      Section l = s.section("lmi");
      YAML::Node lam = l.raw("lambda");
      if (lam.IsScalar() && lam.as<std::string>() == "search") {
        y.lmi_lambda = "search";
      } else {
        y.lmi_lambda = std::to_string(l.number_in("lambda", 1e-6, 1.0 - 1e-9));
      }
      y.lmi_w_floor = l.number_in("w_floor", 0.0, 1.0);
      y.lmi_vertices = l.flag("vertices");
      y.lmi_certify_steps = l.integer_in("certify_steps", 0, 100);
      l.finish();
    }
    {
      Section r = s.section("rpi");
      y.rpi_variant = r.text("variant", {"lti", "lpv_thesis", "lpv_robust"});
      y.rpi_lambda = r.number_in("lambda", 1e-9, 1.0 - 1e-9);
      y.verify_directions = r.integer_in("verify_directions", 0, 1000000);
      r.finish();
    }
    {
      Section w = s.section("uncertainty");
      y.w_source = w.text("source", {"box", "sampled"});
      YAML::Node f = w.raw("state_fraction");
      if (f.IsSequence()) {
        y.w_state_fraction = to_eigen(w.vector("state_fraction", static_cast<std::size_t>(n)));
      } else {
        y.w_state_fraction = Eigen::VectorXd::Constant(n, w.number("state_fraction"));
      }
      for (int i = 0; i < n; ++i) {
        if (!(y.w_state_fraction[i] >= 0.0 && y.w_state_fraction[i] < 1.0)) {
          w.fail(w.key("state_fraction"), "must be in [0, 1)");
        }
      }
      const long nd = c.model == ModelKind::Tiltrotor ? 3 : c.linear.D.cols();
      y.w_disturbance = to_eigen(w.vector("disturbance", static_cast<std::size_t>(nd)));
      if ((y.w_disturbance.array() < 0.0).any()) w.fail(w.key("disturbance"), "half-widths must be >= 0");
      y.w_samples = w.integer_in("samples", 1, 10000000);
      y.w_sample_fraction = w.number_in("sample_fraction", 0.0, 0.9);
      y.w_sample_box = w.number_in("sample_box", 0.0, 1.0);
      if (w.has("seed")) y.w_seed = static_cast<unsigned>(w.integer_in("seed", 0, 2147483647L));
      w.finish();
      if (c.model == ModelKind::Linear && y.w_source == "sampled") {
        w.fail(w.key("source"), "sampled W needs the tiltrotor's nonlinear model (use box for a linear model)");
      }
    }
    y.terminal_cost = s.text("terminal_cost", {"lqr", "lmi"});
    y.horizon = s.integer_in("horizon", 1, kMaxHorizon);
    y.control_horizon = s.integer_in("control_horizon", 1, kMaxHorizon);
    if (y.control_horizon > y.horizon) s.fail(s.key("control_horizon"), "must be <= horizon (M <= N)");
    s.finish();
  }

  if (root.has("explicit")) {
    Section s = root.section("explicit");
    ExplicitSettings& e = c.explicit_mpc;
    e.horizon = s.integer_in("horizon", 1, 100);
    e.control_horizon = s.integer_in("control_horizon", 1, 100);
    if (e.control_horizon > e.horizon) s.fail(s.key("control_horizon"), "must be <= horizon (M <= N)");
    e.domain_fraction = s.number_in("domain_fraction", 1e-6, 1.0);
    e.max_regions = s.integer_in("max_regions", 1, 10000000);
    e.time_limit_s = s.number_in("time_limit_s", 1e-3, 1e6);
    s.finish();
  }
  if (root.has("link")) {
    Section s = root.section("link");
    LinkSettings& l = c.link;
    auto opt = [&](const char* k, double& v, double lo, double hi) {
      if (s.has(k)) v = s.number_in(k, lo, hi);
    };
    auto opt_int = [&](const char* k, int& v, int lo, int hi) {
      if (s.has(k)) v = s.integer_in(k, lo, hi);
    };
    opt_int("watchdog_periods", l.watchdog_periods, 1, 100000);
    opt("plant_hold_s", l.plant_hold_s, 0.0, 1e4);
    if (s.has("bounds")) {
      Section b = s.section("bounds");
      auto bound = [&](const char* k, double& v) {
        if (b.has(k)) v = b.positive(k);
      };
      bound("position", l.bound_position);
      bound("angle", l.bound_angle);
      bound("yaw", l.bound_yaw);
      bound("velocity", l.bound_velocity);
      bound("angular_rate", l.bound_rate);
      bound("time", l.bound_time);
      b.finish();
    }
    if (s.has("jump")) {
      Section j = s.section("jump");
      auto jump = [&](const char* k, double& v) {
        if (j.has(k)) v = j.positive(k);
      };
      jump("position", l.jump_position);
      jump("angle", l.jump_angle);
      jump("velocity", l.jump_velocity);
      jump("angular_rate", l.jump_rate);
      j.finish();
    }
    opt("time_tolerance", l.time_tolerance, 1e-3, 10.0);
    opt_int("gate_horizon", l.gate_horizon, 1, 100000);
    opt_int("resync_frames", l.resync_frames, 2, 1000);
    opt_int("session_confirm", l.session_confirm, 1, 1000);
    opt_int("sequence_window", l.sequence_window, 1, 1 << 29);
    s.finish();
  }
  root.finish();
  (void)p;
  return c;
}

/// What the model can only tell once the whole vehicle is known: a hover equilibrium
/// exists and its inputs are inside the actuator limits.
void check_physics(const Config& c) {
  Equilibrium eq;
  try {
    eq = solve_hover_equilibrium(TiltrotorModel(c.vehicle), c.envelope.yaw);
  } catch (const std::exception& e) {
    throw ConfigError(c.source + ": vehicle: no hover equilibrium for these parameters (" + e.what() + ")");
  }
  static const char* const names[4] = {"right thrust f_r", "left thrust f_l", "right servo torque tau_r",
                                       "left servo torque tau_l"};
  const double mass = c.vehicle.load_mass + c.vehicle.body_mass + 2.0 * c.vehicle.rotor_mass;
  for (int i = 0; i < 4; ++i) {
    const bool low = eq.u(i) < c.input_min(i), high = eq.u(i) > c.input_max(i);
    if (!low && !high) continue;
    std::ostringstream os;
    os << "the hover " << names[i] << " is " << eq.u(i) << (i < 2 ? " N" : " N m") << ", "
       << (high ? "above the limit " : "below the limit ") << (high ? c.input_max(i) : c.input_min(i))
       << " (vehicle mass " << mass << " kg: check vehicle masses or the limits)";
    throw ConfigError(c.source + ": constraints." + (high ? "input_max[" : "input_min[") + std::to_string(i) +
                      "]: " + os.str());
  }
}

}  // namespace

Eigen::Vector3d EnvelopeSettings::in_design_frame(const Eigen::Vector3d& v, double psi_r) const {
  if (!any_yaw()) return v;
  const double c = std::cos(psi_r - yaw), s = std::sin(psi_r - yaw);
  return {c * v(0) + s * v(1), -s * v(0) + c * v(1), v(2)};
}

std::string EnvelopeSettings::yaw_text() const {
  std::ostringstream os;
  if (any_yaw()) {
    os << "any yaw at up to " << yaw_rate_max << " rad/s (the model's yaw " << yaw
       << " rad, horizontal errors in the reference's yaw frame)";
  } else {
    os << "yaw " << yaw << " +- " << yaw_tolerance << " rad";
  }
  return os.str();
}

int Config::measured() const { return model == ModelKind::Tiltrotor ? kNx : static_cast<int>(linear.A.rows()); }

int Config::integrals() const { return static_cast<int>(integrated().size()); }

int Config::inputs() const { return model == ModelKind::Tiltrotor ? kNu : static_cast<int>(linear.B.cols()); }

std::vector<int> Config::integrated() const {
  if (model == ModelKind::Linear) return linear.integrated;
  return {kX, kY, kZ, kPsi};
}

std::vector<std::string> Config::state_names() const {
  std::vector<std::string> names;
  if (model == ModelKind::Linear) {
    names = linear.state_names;
  } else {
    for (const char* q : kCoordNames) names.emplace_back(q);
    for (const char* q : kCoordNames) names.push_back(std::string("d_") + q);
  }
  for (int i : integrated()) names.push_back("int_" + names[static_cast<std::size_t>(i)]);
  return names;
}

std::vector<StateKind> Config::state_kinds() const {
  std::vector<StateKind> k = model == ModelKind::Linear ? linear.kinds : tiltrotor_state_kinds();
  if (model == ModelKind::Linear) k.resize(k.size() + integrated().size(), StateKind::Integral);
  return k;
}

std::vector<std::string> Config::input_names() const {
  if (model == ModelKind::Linear) return linear.input_names;
  return {"f_r", "f_l", "tau_r", "tau_l"};
}

Eigen::Matrix3d VehicleParams::rotor_inertia_about_com() const {
  if (rotor_inertia_reference == RotorInertiaReference::Com) return rotor_inertia;
  // Parallel-axis theorem: I_pivot = I_com + m (|c|^2 I - c c').
  const Eigen::Vector3d& c = rotor_com;
  return rotor_inertia - rotor_mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

Config load_config_from_string(const std::string& yaml, const std::string& source) {
  Config c = parse(detail::load_single_document(yaml, source), source);
  if (c.model == ModelKind::Tiltrotor) check_physics(c);
  return c;
}

std::string read_config_file(const std::string& path, const char* what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw ConfigError(path + ": cannot open the " + what + ": " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw ConfigError(path + ": is a directory, not a " + what + " file");
  if (!S_ISREG(st.st_mode)) {
    throw ConfigError(path + ": not a regular file (a device, pipe or socket cannot be a " + what + ")");
  }
  if (st.st_size > kMaxConfigBytes) {
    throw ConfigError(path + ": " + std::to_string(st.st_size) + " bytes: too large for a " + what + " (limit " +
                      std::to_string(kMaxConfigBytes) + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open the " + what);
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  in.read(text.data(), st.st_size);
  text.resize(static_cast<std::size_t>(in.gcount()));
  return text;
}

namespace {

/// `over` laid over `base`: mappings merged key by key (recursively), anything else
/// replaced. A key given twice in `over` is an error (yaml-cpp would keep both).
YAML::Node merged(const YAML::Node& base, const YAML::Node& over, const std::string& source, const std::string& path) {
  if (!over.IsMap() || !base.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  std::set<std::string> seen;
  for (const auto& kv : over) {
    if (!kv.first.IsScalar()) throw ConfigError(source + ": " + (path.empty() ? "(top level)" : path) + ": a key must be a plain name");
    const std::string k = kv.first.Scalar();
    const std::string key = path.empty() ? k : path + "." + k;
    if (!seen.insert(k).second) throw ConfigError(source + ": " + key + ": duplicate key (only one value is allowed)");
    out[k] = base[k] ? merged(base[k], kv.second, source, key) : YAML::Clone(kv.second);
  }
  return out;
}

YAML::Node resolved_node(const std::string& path, int depth) {
  YAML::Node root = detail::load_single_document(read_config_file(path, "configuration"), path);
  if (!root.IsMap() || !root["base"]) return root;
  if (depth >= 4) throw ConfigError(path + ": base: more than 4 levels of base configurations (a cycle?)");
  const YAML::Node b = root["base"];
  if (!b.IsScalar()) throw ConfigError(path + ": base: expected a file name");
  const std::string file = b.Scalar();
  const std::string base_path = !file.empty() && file[0] == '/' ? file : detail::folder_of(path) + file;
  YAML::Node over = YAML::Clone(root);
  over.remove("base");
  return merged(resolved_node(base_path, depth + 1), over, path, "");
}

}  // namespace

std::string read_config_text(const std::string& path) {
  const std::string text = read_config_file(path, "configuration");
  const YAML::Node root = detail::load_single_document(text, path);
  if (!root.IsMap() || !root["base"]) return text;  // as written, comments kept
  YAML::Emitter out;
  out << YAML::Comment("merged from " + path + " and its base configuration") << resolved_node(path, 0);
  if (!out.good()) throw ConfigError(path + ": cannot write the merged configuration: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

Config load_config(const std::string& path) { return load_config_from_string(read_config_text(path), path); }

}  // namespace tmpc
