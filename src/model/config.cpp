// YAML loading and validation of the design configuration.
#include "tmpc/model/config.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <yaml-cpp/yaml.h>

#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/equilibrium.hpp"

namespace tmpc {

namespace {

/// A YAML mapping with its dotted path; every access is checked and every key
/// that is not read is reported as unknown by finish().
class Section {
 public:
  Section(YAML::Node node, std::string path, const std::string& file)
      : node_(std::move(node)), path_(std::move(path)), file_(file) {
    if (!node_ || !node_.IsMap()) fail(path_.empty() ? "(top level)" : path_, "expected a mapping");
    // yaml-cpp keeps every duplicate and node[k] returns the first: a later value of
    // the same key would be ignored silently. Keys must also be plain names.
    std::set<std::string> seen;
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar()) {
        fail(path_.empty() ? "(top level)" : path_,
             "a key must be a plain name, found a " + std::string(kv.first.IsSequence() ? "list" : "mapping") +
                 " at line " + std::to_string(kv.first.Mark().line + 1));
      }
      const std::string k = kv.first.Scalar();
      if (!seen.insert(k).second) {
        fail(key(k), "duplicate key (again at line " + std::to_string(kv.first.Mark().line + 1) +
                         "; only one value is allowed)");
      }
    }
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw ConfigError(file_ + ": " + key + ": " + what);
  }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  YAML::Node raw(const std::string& k) {
    used_.insert(k);
    YAML::Node n = node_[k];
    if (!n) fail(key(k), "missing");
    return n;
  }
  bool has(const std::string& k) const { return static_cast<bool>(node_[k]); }

  Section section(const std::string& k) { return Section(raw(k), key(k), file_); }

  double number(const std::string& k) {
    YAML::Node n = raw(k);
    return to_number(n, key(k));
  }
  double number_in(const std::string& k, double lo, double hi) {
    const double v = number(k);
    if (v < lo || v > hi) {
      std::ostringstream os;
      os << "out of range: " << v << " not in [" << lo << ", " << hi << "]";
      fail(key(k), os.str());
    }
    return v;
  }
  /// A whole number in [lo, hi] ("horizon: 20.7" is an error, not 20).
  int integer_in(const std::string& k, long lo, long hi) {
    const double v = number(k);
    if (std::floor(v) != v) fail(key(k), "expected a whole number, got " + fmt(v));
    if (v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
      fail(key(k), "out of range: " + fmt(v) + " not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return static_cast<int>(v);
  }
  double positive(const std::string& k) {
    const double v = number(k);
    if (!(v > 0.0)) fail(key(k), "must be positive (got " + fmt(v) + ")");
    return v;
  }
  std::string text(const std::string& k, std::initializer_list<const char*> allowed) {
    YAML::Node n = raw(k);
    if (!n.IsScalar()) fail(key(k), "expected a string");
    const std::string s = n.as<std::string>();
    std::string list;
    for (const char* a : allowed) {
      if (s == a) return s;
      list += list.empty() ? a : std::string(", ") + a;
    }
    fail(key(k), "unknown value '" + s + "' (expected one of: " + list + ")");
  }
  bool flag(const std::string& k) {
    YAML::Node n = raw(k);
    if (!n.IsScalar()) fail(key(k), "expected true or false");
    const std::string v = n.as<std::string>();
    if (v == "true") return true;
    if (v == "false") return false;
    fail(key(k), "expected true or false, got '" + v + "'");
  }
  std::vector<double> vector(const std::string& k, std::size_t n) {
    return vector_of(raw(k), key(k), n);
  }
  std::vector<double> vector_of(const YAML::Node& node, const std::string& name, std::size_t n) const {
    if (!node.IsSequence()) fail(name, "expected a list of " + std::to_string(n) + " numbers");
    if (node.size() != n) {
      fail(name, "expected " + std::to_string(n) + " values, got " + std::to_string(node.size()));
    }
    std::vector<double> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = to_number(node[i], name + "[" + std::to_string(i) + "]");
    return out;
  }

  /// Report keys that were never read (typos, unsupported options).
  void finish() const {
    for (const auto& kv : node_) {
      const std::string k = kv.first.Scalar();
      if (used_.count(k) == 0) fail(key(k), "unknown key");
    }
  }

 private:
  static std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }
  double to_number(const YAML::Node& n, const std::string& name) const {
    if (!n.IsScalar()) fail(name, "expected a number");
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(name, "expected a number, got '" + n.as<std::string>() + "'");
    }
    if (!std::isfinite(v)) fail(name, "must be finite (got " + n.as<std::string>() + ")");
    return v;
  }

  YAML::Node node_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> used_;
};

Eigen::Vector3d vec3(Section& s, const std::string& k) {
  const auto v = s.vector(k, 3);
  return {v[0], v[1], v[2]};
}

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

template <int N>
Eigen::Matrix<double, N, 1> to_eigen(const std::vector<double>& v) {
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) out[i] = v[static_cast<std::size_t>(i)];
  return out;
}

Config parse(const YAML::Node& root_node, const std::string& source) {
  Config c;
  c.source = source;
  Section root(root_node, "", c.source);

  load_vehicle(root.section("vehicle"), c.vehicle);

  {
    Section s = root.section("reference");
    c.reference.radius = s.number_in("radius", 0.0, 1e4);
    c.reference.center_x = s.number("center_x");
    c.reference.center_y = s.number("center_y");
    c.reference.z_offset = s.number("z_offset");
    c.reference.z_amplitude = s.number_in("z_amplitude", 0.0, 1e4);
    c.reference.angular_rate = s.number_in("angular_rate", 0.0, 100.0);
    c.reference.yaw = s.number_in("yaw", -M_PI, M_PI);
    c.reference.attitude = s.text("attitude", {"trim", "equilibrium"}) == "trim" ? ReferenceAttitude::Trim
                                                                               : ReferenceAttitude::Equilibrium;
    s.finish();
  }

  c.sample_time = root.number_in("sample_time", 1e-5, 1.0);

  {
    Section s = root.section("constraints");
    c.input_min = to_eigen<4>(s.vector("input_min", 4));
    c.input_max = to_eigen<4>(s.vector("input_max", 4));
    for (int i = 0; i < 4; ++i) {
      if (!(c.input_max[i] > c.input_min[i])) {
        s.fail(s.key("input_max") + "[" + std::to_string(i) + "]", "must exceed input_min");
      }
    }
    if (c.input_min[0] < 0.0 || c.input_min[1] < 0.0) {
      s.fail(s.key("input_min"), "thrusts cannot be negative");
    }
    c.state_error_max = to_eigen<24>(s.vector("state_error_max", 24));
    for (int i = 0; i < 24; ++i) {
      if (!(c.state_error_max[i] > 0.0)) {
        s.fail(s.key("state_error_max") + "[" + std::to_string(i) + "]", "half-width must be positive");
      }
    }
    s.finish();
  }

  {
    Section s = root.section("weights");
    c.input_weights = to_eigen<4>(s.vector("input", 4));
    c.state_weights = to_eigen<24>(s.vector("state", 24));
    for (int i = 0; i < 4; ++i) {
      if (!(c.input_weights[i] > 0.0)) {
        s.fail(s.key("input") + "[" + std::to_string(i) + "]", "weight must be positive");
      }
    }
    for (int i = 0; i < 24; ++i) {
      if (!(c.state_weights[i] > 0.0)) {
        s.fail(s.key("state") + "[" + std::to_string(i) + "]", "weight must be positive");
      }
    }
    s.finish();
  }

  {
    Section s = root.section("disturbance");
    YAML::Node steps = s.raw("steps");
    const std::string name = s.key("steps");
    if (!steps.IsSequence()) s.fail(name, "expected a list of {time, force}");
    double last = -1.0;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      Section step(steps[i], name + "[" + std::to_string(i) + "]", c.source);
      DisturbanceStep d;
      d.time = step.number_in("time", 0.0, 1e6);
      if (d.time < last) step.fail(step.key("time"), "steps must be in time order");
      last = d.time;
      d.force = vec3(step, "force");
      step.finish();
      c.disturbances.push_back(d);
    }
    s.finish();
  }

  {
    Section s = root.section("perturbation");
    c.perturbation.fraction = s.number_in("fraction", 0.0, 0.9);
    c.perturbation.distribution = s.text("distribution", {"uniform", "normal"});
    c.perturbation.seed = static_cast<unsigned>(s.integer_in("seed", 0, 2147483647L));
    c.perturbation.runs = s.integer_in("runs", 1, 1000000);
    s.finish();
  }

  {
    Section s = root.section("simulation");
    c.simulation.duration = s.number_in("duration", 0.0, 1e6);
    c.simulation.substep = s.number_in("substep", 1e-6, 0.1);
    c.simulation.plant = s.text("plant", {"el", "mujoco"});
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
    c.error_model.lpv_sample_step = s.number_in("lpv_sample_step", 1e-3, 100.0);
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
    s.finish();
  }

  {
    Section s = root.section("synthesis");
    SynthesisSettings& y = c.synthesis;
    y.tube_gain = s.text("tube_gain", {"lqr", "lmi_thesis", "lmi_robust"});
    y.compare_gains = s.flag("compare_gains");
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
        y.w_state_fraction = to_eigen<24>(w.vector("state_fraction", 24));
      } else {
        y.w_state_fraction.setConstant(w.number("state_fraction"));
      }
      for (int i = 0; i < 24; ++i) {
        if (!(y.w_state_fraction[i] >= 0.0 && y.w_state_fraction[i] < 1.0)) {
          w.fail(w.key("state_fraction"), "must be in [0, 1)");
        }
      }
      y.w_disturbance = vec3(w, "disturbance");
      if ((y.w_disturbance.array() < 0.0).any()) w.fail(w.key("disturbance"), "half-widths must be >= 0");
      y.w_samples = w.integer_in("samples", 1, 10000000);
      y.w_sample_fraction = w.number_in("sample_fraction", 0.0, 0.9);
      y.w_sample_box = w.number_in("sample_box", 0.0, 1.0);
      w.finish();
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
  return c;
}

/// What the model can only tell once the whole vehicle is known: a hover equilibrium
/// exists and its inputs are inside the actuator limits.
void check_physics(const Config& c) {
  Equilibrium eq;
  try {
    eq = solve_hover_equilibrium(TiltrotorModel(c.vehicle), c.reference.yaw);
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

Eigen::Matrix3d VehicleParams::rotor_inertia_about_com() const {
  if (rotor_inertia_reference == RotorInertiaReference::Com) return rotor_inertia;
  // Parallel-axis theorem: I_pivot = I_com + m (|c|^2 I - c c').
  const Eigen::Vector3d& c = rotor_com;
  return rotor_inertia - rotor_mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

Config load_config_from_string(const std::string& yaml, const std::string& source) {
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(yaml);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ": YAML syntax error: " + e.what());
  }
  if (docs.empty()) throw ConfigError(source + ": (top level): the file is empty");
  if (docs.size() > 1) {
    throw ConfigError(source + ": a second YAML document starts at line " + std::to_string(docs[1].Mark().line + 1) +
                      " (a configuration is one document; remove the '---' or split the file)");
  }
  Config c = parse(docs[0], source);
  check_physics(c);
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

Config load_config(const std::string& path) { return load_config_from_string(read_config_file(path, "configuration"), path); }

}  // namespace tmpc
