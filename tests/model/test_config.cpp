// Config loading: the default file loads, and every class of malformed input is an
// error that names the file and the key.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace tmpc {
namespace {

std::string default_text() {
  std::ifstream in(std::string(TMPC_SOURCE_DIR) + "/config/tiltrotor.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Replace the first occurrence of `from` in the default config and load it;
/// return the error message ("" when it loads).
std::string load_with(const std::string& from, const std::string& to) {
  std::string text = default_text();
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture text not found: " << from;
  text.replace(pos, from.size(), to);
  try {
    load_config_from_string(text, "bad.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& msg, const std::string& key, const std::string& what) {
  EXPECT_NE(msg.find("bad.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find(key), std::string::npos) << "key '" << key << "' not named in: " << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << "'" << what << "' not in: " << msg;
}

TEST(Config, DefaultLoadsWithTheCaseStudyNumbers) {
  const Config& c = test::default_config();
  EXPECT_DOUBLE_EQ(c.vehicle.load_mass, 0.5);
  EXPECT_DOUBLE_EQ(c.vehicle.body_mass, 1.7068);
  EXPECT_DOUBLE_EQ(c.vehicle.rotor_mass, 0.08978);
  EXPECT_DOUBLE_EQ(c.sample_time, 0.012);
  EXPECT_DOUBLE_EQ(c.input_max(0), 30.0);
  EXPECT_DOUBLE_EQ(c.input_min(2), -2.0);
  EXPECT_DOUBLE_EQ(c.state_error_max(16), 2.0);  // gamma_1 rate, E10 order
  EXPECT_DOUBLE_EQ(c.state_error_max(18), 0.2);  // alpha_r rate
  EXPECT_DOUBLE_EQ(c.input_weights(2), 38.730);
  EXPECT_DOUBLE_EQ(c.state_weights(23), 0.158);
  EXPECT_DOUBLE_EQ(c.synthesis.lqr_input_scale(1), 1.0);    // the tube gain's thrust weights: lambda's
  EXPECT_DOUBLE_EQ(c.synthesis.lqr_input_scale(2), 100.0);  // its servo torques': 100 lambda
  EXPECT_EQ(c.model, ModelKind::Tiltrotor);
  EXPECT_EQ(c.states(), 24);
  EXPECT_EQ(c.measured(), 20);
  EXPECT_EQ(c.inputs(), 4);
  EXPECT_EQ(c.integrated(), (std::vector<int>{0, 1, 2, 5}));
  EXPECT_EQ(c.state_names()[7], "gamma_2");
  EXPECT_EQ(c.state_names()[23], "int_psi");
  EXPECT_DOUBLE_EQ(c.envelope.acceleration_max.y(), 0.06);
  EXPECT_DOUBLE_EQ(c.envelope.acceleration_min.z(), -0.04);
  EXPECT_EQ(c.envelope.trajectories.size(), 5u);
  EXPECT_DOUBLE_EQ(c.solver.admm_eta, 0.999);
  EXPECT_EQ(c.vehicle.rotor_inertia_reference, RotorInertiaReference::Com);
  EXPECT_EQ(c.error_model.discretization, Discretization::Zoh);
}

TEST(Config, TheEnvelopeFliesAnyYawAtABoundedRateOrOneFixedYaw) {
  EXPECT_TRUE(test::default_config().envelope.any_yaw());
  EXPECT_DOUBLE_EQ(test::default_config().envelope.yaw_rate_max, 0.2);
  // A fixed-yaw design: yaw_tolerance instead.
  std::string text = default_text();
  const std::string from = "yaw_rate_max: 0.2";
  text.replace(text.find(from), from.size(), "yaw_tolerance: 0.05");
  const Config fixed = load_config_from_string(text, "fixed.yaml");
  EXPECT_FALSE(fixed.envelope.any_yaw());
  EXPECT_DOUBLE_EQ(fixed.envelope.yaw_tolerance, 0.05);
  // The horizontal components turn into the reference's yaw frame; z and a fixed-yaw
  // design's vectors are kept.
  const Eigen::Vector3d a(0.03, 0.0, -0.01);
  const Eigen::Vector3d turned = test::default_config().envelope.in_design_frame(a, M_PI / 2);
  EXPECT_NEAR(turned.x(), 0.0, 1e-15);
  EXPECT_NEAR(turned.y(), -0.03, 1e-15);  // a vehicle facing +y sees +x on its right
  EXPECT_DOUBLE_EQ(turned.z(), -0.01);
  EXPECT_EQ(fixed.envelope.in_design_frame(a, M_PI / 2), a);
  expect_error(load_with("yaw_rate_max: 0.2", "yaw_rate_max: 0.2\n  yaw_tolerance: 0.05"), "envelope.yaw_tolerance",
               "not both");
  expect_error(load_with("yaw_rate_max: 0.2", "yaw_rate_max: -0.1"), "envelope.yaw_rate_max", "out of range");
  expect_error(load_with("yaw_rate_max: 0.2", "yaw_rate_max: .nan"), "envelope.yaw_rate_max", "finite");
  expect_error(load_with("  yaw_rate_max: 0.2", ""), "envelope.yaw_tolerance", "missing");
}

TEST(Config, UnknownKeyIsNamed) {
  expect_error(load_with("rod_length: 0.5", "rod_length: 0.5\n  rod_lenght: 0.5"), "vehicle.rod_lenght",
               "unknown key");
  expect_error(load_with("sample_time: 0.012", "sample_time: 0.012\nsampel: 1"), "sampel", "unknown key");
}

TEST(Config, WrongVectorLengthIsNamed) {
  expect_error(load_with("input: [1.642, 1.646, 38.730, 38.730]", "input: [1.642, 1.646, 38.730]"),
               "weights.input", "expected 4 values, got 3");
  expect_error(load_with("friction: [0, 0, 0, 0, 0, 0, 0.005, 0.005, 0.005, 0.005]", "friction: [0, 0]"),
               "vehicle.friction", "expected 10 values, got 2");
}

TEST(Config, NonFiniteValueIsNamed) {
  expect_error(load_with("mass: 0.5", "mass: .nan"), "vehicle.load.mass", "finite");
  expect_error(load_with("speed_max: 1.0", "speed_max: .inf"), "envelope.speed_max", "finite");
}

TEST(Config, OutOfRangeValueIsNamed) {
  expect_error(load_with("dihedral: 0.0872665", "dihedral: 3.0"), "vehicle.rotor.dihedral", "out of range");
  expect_error(load_with("admm_eta: 0.999", "admm_eta: 1.5"), "solver.admm_eta", "out of range");
  expect_error(load_with("input_min: [0.0, 0.0, -2.0, -2.0]", "input_min: [0.0, 0.0, 3.0, -2.0]"),
               "constraints.input_max[2]", "must exceed");
}

TEST(Config, NonPositiveWeightIsNamed) {
  expect_error(load_with("input: [1.642, 1.646, 38.730, 38.730]", "input: [1.642, 0.0, 38.730, 38.730]"),
               "weights.input[1]", "positive");
  expect_error(load_with("state: [1.265,", "state: [-1.265,"), "weights.state[0]", "positive");
  // The optional input-rate weight: zeros without it, >= 0 entries, one per input.
  const std::string rate = "input: [1.642, 1.646, 38.730, 38.730]";
  expect_error(load_with(rate, rate + "\n  input_rate: [1.0, -2.0, 0.0, 0.0]"), "weights.input_rate[1]", ">= 0");
  expect_error(load_with(rate, rate + "\n  input_rate: [1.0, 2.0]"), "weights.input_rate", "");
  const Config plain = load_config_from_string(default_text(), "tiltrotor.yaml");
  EXPECT_EQ(plain.input_rate_weights, Eigen::VectorXd::Zero(4));
  const Config rated = load_config_from_string(
      [&] {
        std::string t = default_text();
        t.replace(t.find(rate), rate.size(), rate + "\n  input_rate: [0.0, 0.5, 10.0, 10.0]");
        return t;
      }(),
      "rated.yaml");
  EXPECT_EQ(rated.input_rate_weights, Eigen::Vector4d(0.0, 0.5, 10.0, 10.0));
  expect_error(load_with("mass: 1.7068", "mass: -1.7068"), "vehicle.body.mass", "positive");
}

TEST(Config, MissingKeyWrongTypeAndBadEnumAreNamed) {
  expect_error(load_with("  rod_length: 0.5", "  # rod_length: 0.5"), "vehicle.rod_length", "missing");
  expect_error(load_with("speed_max: 1.0", "speed_max: five"), "envelope.speed_max", "expected a number");
  expect_error(load_with("discretization: zoh", "discretization: tustin"), "error_model.discretization",
               "unknown value 'tustin'");
  expect_error(load_with("spin_left: -1", "spin_left: 2"), "vehicle.rotor.spin_left", "+1 or -1");
}

TEST(Config, InvalidInertiaIsNamed) {
  expect_error(load_with("inertia: [8.333e-6, 0, 0,", "inertia: [-8.333e-6, 0, 0,"), "vehicle.load.inertia",
               "positive definite");
}

TEST(Config, SyntaxErrorAndMissingFile) {
  EXPECT_THROW(load_config_from_string("vehicle: [unclosed", "broken.yaml"), ConfigError);
  try {
    load_config("/nonexistent/tmpc.yaml");
    FAIL() << "no error for a missing file";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/tmpc.yaml"), std::string::npos);
  }
}


TEST(Config, DuplicateKeysAreErrorsNotASilentFirstValue) {
  // mass: 50 then mass: 0.5 under vehicle.load: yaml-cpp would hand out the first.
  expect_error(load_with("    mass: 0.5", "    mass: 50.0\n    mass: 0.5"), "vehicle.load.mass", "duplicate key");
  expect_error(load_with("sample_time: 0.012", "sample_time: 0.012\nsample_time: 0.024"), "sample_time",
               "duplicate key");
}

TEST(Config, KeysMustBePlainNames) {
  expect_error(load_with("sample_time: 0.012", "sample_time: 0.012\n[a, b]: 1"), "(top level)",
               "a key must be a plain name, found a list");
  expect_error(load_with("  rod_length: 0.5", "  rod_length: 0.5\n  {a: 1}: 2"), "vehicle",
               "a key must be a plain name, found a mapping");
}

TEST(Config, IntegersMustBeWhole) {
  expect_error(load_with("horizon: 20 ", "horizon: 20.7 "), "synthesis.horizon", "expected a whole number, got 20.7");
  expect_error(load_with("envelope_grid: 5", "envelope_grid: 2.5"), "error_model.envelope_grid", "whole number");
  expect_error(load_with("horizon: 20 ", "horizon: 5000 "), "synthesis.horizon", "out of range");
}

TEST(Config, ASecondYamlDocumentIsAnError) {
  std::string text = default_text() + "\n---\nsample_time: 0.5\n";
  try {
    load_config_from_string(text, "bad.yaml");
    FAIL() << "a second document was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml: a second YAML document starts at line"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_config_from_string("", "empty.yaml"), ConfigError);
}

TEST(Config, AStrayCommaIsASyntaxErrorNotAHang) {
  // yaml-cpp 0.7's LoadAll loops forever (allocating) on these (jbeder/yaml-cpp#1040);
  // found by fuzzing the config and scenario loaders. A hang here is ctest's timeout.
  for (const std::string& text : std::vector<std::string>{",", "\n,\n", ",\n" + default_text(), "- !+(.,.)"}) {
    std::string msg;
    try {
      load_config_from_string(text, "bad.yaml");
    } catch (const ConfigError& e) {
      msg = e.what();
    }
    EXPECT_NE(msg.find("bad.yaml: YAML syntax error"), std::string::npos) << "'" << text.substr(0, 20) << "': " << msg;
  }
  const std::string text = default_text();
  std::string msg;
  try {
    load_config_from_string(text + "\n---\nsample_time: 0.5\n", "bad.yaml");
  } catch (const ConfigError& e) {
    msg = e.what();
  }
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  EXPECT_NE(msg.find("second YAML document starts at line " + std::to_string(lines + 2)), std::string::npos) << msg;
}

TEST(Config, NonPhysicalInertiasAreRefused) {
  // Principal moments 1, 1, 5 (x 1e-3): no mass distribution has them (1 + 1 < 5).
  std::string text = default_text();
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"[4047.04e-6, 0.860582e-6, 9.65766e-6,", "[1.0e-3, 0.0, 0.0,"},
                                 {"0.860582e-6, 881.618e-6, -0.873079e-6,", "0.0, 1.0e-3, 0.0,"},
                                 {"9.65766e-6, -0.873079e-6, 4173.18e-6]", "0.0, 0.0, 5.0e-3]"}}) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  }
  std::string msg;
  try {
    load_config_from_string(text, "bad.yaml");
  } catch (const ConfigError& e) {
    msg = e.what();
  }
  expect_error(msg, "vehicle.body.inertia", "violate the triangle inequality");
}

TEST(Config, AHoverThrustOutsideTheInputLimitsIsNamed) {
  // A 50 kg load needs about 255 N of thrust against a 30 N limit per rotor.
  expect_error(load_with("    mass: 0.5", "    mass: 50.0"), "constraints.input_max[0]", "above the limit 30");
  // Limits that leave no room below the hover thrust either.
  expect_error(load_with("input_min: [0.0, 0.0, -2.0, -2.0]", "input_min: [20.0, 0.0, -2.0, -2.0]"),
               "constraints.input_min[0]", "below the limit 20");
}

TEST(Config, LinkSectionIsOptionalAndValidated) {
  const Config& c = test::default_config();
  EXPECT_EQ(c.link.watchdog_periods, 10);
  EXPECT_DOUBLE_EQ(c.link.plant_hold_s, 0.1);
  expect_error(load_with("  resync_frames: 3 ", "  resync_frames: 1 "), "link.resync_frames", "out of range");
  expect_error(load_with("    position: 1000.0 ", "    speed: 3\n    position: 1000.0 "), "link.bounds.speed",
               "unknown key");
  // The whole section may go (defaults), and a jump threshold may be set.
  std::string text = default_text();
  text = text.substr(0, text.find("\nlink:")) + "\nlink: {watchdog_periods: 4, jump: {position: 0.2}}\n";
  const Config c2 = load_config_from_string(text, "ok.yaml");
  EXPECT_EQ(c2.link.watchdog_periods, 4);
  EXPECT_DOUBLE_EQ(c2.link.jump_position, 0.2);
  EXPECT_EQ(c2.link.resync_frames, 3);
}

TEST(Config, SpecialAndHugeFilesAreClearErrors) {
  auto message = [](const std::string& path) {
    try {
      load_config(path);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("/dev/zero").find("/dev/zero: not a regular file"), std::string::npos) << message("/dev/zero");
  EXPECT_NE(message("/tmp").find("/tmp: is a directory"), std::string::npos);
  const std::string big = ::testing::TempDir() + "huge_config.yaml";
  {
    std::ofstream out(big);
    out << default_text();
    out << std::string(static_cast<std::size_t>(kMaxConfigBytes), '#') << "\n";
  }
  EXPECT_NE(message(big).find("too large"), std::string::npos) << message(big);
}


// A configuration that names a base: the base's keys with its own laid over them.
TEST(Config, ABaseConfigurationIsMergedKeyByKey) {
  const std::string dir = ::testing::TempDir() + "base_cfg/";
  std::system(("mkdir -p " + dir).c_str());
  {
    std::ofstream(dir + "base.yaml") << default_text();
    std::ofstream(dir + "derived.yaml") << "base: base.yaml\nsample_time: 0.012\nsynthesis:\n  horizon: 10\n"
                                           "  lqr_input_scale: [1, 1, 5, 5]\ntube_law: {offset_free: true, observer_gain: 0.2}\n";
  }
  const Config c = load_config(dir + "derived.yaml");
  EXPECT_EQ(c.synthesis.horizon, 10);                 // replaced inside the merged mapping
  EXPECT_EQ(c.synthesis.control_horizon, 4);          // kept from the base
  EXPECT_EQ(c.synthesis.tube_gain, "lqr");
  EXPECT_DOUBLE_EQ(c.synthesis.lqr_input_scale(2), 5.0);
  EXPECT_DOUBLE_EQ(c.tube_law.observer_gain, 0.2);
  EXPECT_DOUBLE_EQ(c.vehicle.body_mass, 1.7068);
  // The merged text stands alone (an artifact embeds it): no base key left.
  const std::string merged = read_config_text(dir + "derived.yaml");
  EXPECT_EQ(merged.find("base:"), std::string::npos);
  EXPECT_EQ(load_config_from_string(merged, "merged.yaml").synthesis.horizon, 10);
  // A file without base is returned as written (comments kept).
  EXPECT_EQ(read_config_text(dir + "base.yaml"), default_text());
  auto error = [&](const std::string& text) {
    std::ofstream(dir + "bad.yaml") << text;
    try {
      load_config(dir + "bad.yaml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("base: missing.yaml\n").find("missing.yaml: cannot open"), std::string::npos);
  EXPECT_NE(error("base: base.yaml\nsynthesis: {horizon: 10}\nsynthesis: {horizon: 12}\n").find("synthesis: duplicate key"),
            std::string::npos);
  EXPECT_NE(error("base: bad.yaml\n").find("more than 4 levels"), std::string::npos);  // itself
  EXPECT_NE(error("base: [a]\n").find("base: expected a file name"), std::string::npos);
  EXPECT_NE(error("base: base.yaml\nsynthesis: {horizn: 10}\n").find("synthesis.horizn: unknown key"), std::string::npos);
}

TEST(Config, EstimationAndSoftConstraintSectionsAreOptionalAndValidated) {
  const Config& c = test::default_config();
  EXPECT_EQ(c.estimation.observer, "kalman");  // the shipped design: the switched observer
  EXPECT_DOUBLE_EQ(c.estimation.monitor_residual_below, 0.025);
  EXPECT_DOUBLE_EQ(c.estimation.monitor_filter_above, 0.05);
  EXPECT_DOUBLE_EQ(c.estimation.noise[0], 0.005);
  EXPECT_DOUBLE_EQ(c.estimation.noise[1], 0.00524);
  EXPECT_TRUE(c.soft_constraints.enabled);  // the shipped design softens an infeasible QP
  const Config n = load_config(std::string(TMPC_SOURCE_DIR) + "/config/tiltrotor_noisy.yaml");
  EXPECT_EQ(n.estimation.observer, "kalman");
  EXPECT_DOUBLE_EQ(n.estimation.monitor_residual_below, 0.0);  // noise_monitor: off: the filter always
  EXPECT_DOUBLE_EQ(n.estimation.noise[0], 0.005);
  EXPECT_TRUE(n.soft_constraints.enabled);
  EXPECT_DOUBLE_EQ(n.synthesis.lqr_input_scale(3), 100.0);
  // The shipped configuration without its estimation section (the residual observer):
  // the section below is appended to it.
  std::string plain = default_text();
  {
    const std::size_t a = plain.find("\nestimation:");
    ASSERT_NE(a, std::string::npos);
    std::size_t b = a + 1;
    do b = plain.find('\n', b) + 1;
    while (b < plain.size() && (plain[b] == ' ' || plain[b] == '#' || plain[b] == '\n'));
    plain.erase(a + 1, b - a - 1);
  }
  EXPECT_EQ(load_config_from_string(plain, "plain.yaml").estimation.observer, "residual");  // no section
  const std::string est =
      "\nestimation:\n  observer: kalman\n  measured: all\n  measurement_noise: {position: 0.005, angle: 0.005, "
      "velocity: 0.03, angular_rate: 0.03}\n  process_noise: {state_fraction: 3.0e-5, force: 0.02, residual: 1.0e-4}\n";
  auto with = [&](const std::string& section) {
    try {
      load_config_from_string(plain + section, "bad.yaml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(with(est), "");
  expect_error(with(est + "  output_feedback_tube: maybe\n"), "estimation.output_feedback_tube", "expected true or false");
  expect_error(with(est + "  output_feedback_noise: loud\n"), "estimation.output_feedback_noise", "unknown value 'loud'");
  EXPECT_EQ(with(est + "  output_feedback_noise: gaussian\n"), "");
  EXPECT_EQ(with(est + "  noise_monitor: {residual_below: 0.02, filter_above: 0.05}\n"), "");
  expect_error(with(est + "  noise_monitor: {residual_below: 0.05, filter_above: 0.02}\n"),
               "estimation.noise_monitor.filter_above", "out of range");
  expect_error(with(est + "  noise_monitor: {residual_below: 0.02, filter_above: 0.05, window: 0}\n"),
               "estimation.noise_monitor.window", "out of range");
  std::string residual_monitor = est + "  noise_monitor: {residual_below: 0.02, filter_above: 0.05}\n";
  residual_monitor.replace(residual_monitor.find("observer: kalman"), 16, "observer: residual");
  expect_error(with(residual_monitor), "estimation.noise_monitor", "needs observer: kalman");
  EXPECT_EQ(with(est + "  noise_monitor: off\n"), "");
  // The filter's start prior: the shipped 3 N and half the noise; bad values named.
  EXPECT_DOUBLE_EQ(c.estimation.start_force, 3.0);
  EXPECT_DOUBLE_EQ(c.estimation.start_state, 0.5);
  EXPECT_EQ(with(est + "  start_prior: {force: 2.0, residual: 0.001, state: 0.5}\n"), "");
  expect_error(with(est + "  start_prior: {force: -1.0}\n"), "estimation.start_prior.force", "out of range");
  expect_error(with(est + "  start_prior: {force: 1.0, state: -0.5}\n"), "estimation.start_prior.state", "out of range");
  expect_error(with(est + "  start_prior: {force: 1.0, mass: 2}\n"), "estimation.start_prior.mass", "");
  expect_error(with(est + "  start_prior: {state: 0.5}\n"), "estimation.start_prior.force", "");
  expect_error(with(est + "  noise_monitor: on\n"), "estimation.noise_monitor", "unknown value 'on'");
  std::string bad = est;
  bad.replace(bad.find("observer: kalman"), 16, "observer: luenberger");
  expect_error(with(bad), "estimation.observer", "unknown value 'luenberger'");
  bad = est;
  bad.replace(bad.find("position: 0.005"), 15, "position: -1");
  expect_error(with(bad), "estimation.measurement_noise.position", "must be positive");
  std::string mayne = default_text();
  mayne.replace(mayne.find("offset_free: true"), 17, "offset_free: false");
  try {
    load_config_from_string(mayne, "bad.yaml");  // the shipped Kalman filter with Mayne's law
    ADD_FAILURE() << "a Kalman filter without the offset-free law loaded";
  } catch (const ConfigError& e) {
    expect_error(e.what(), "estimation.observer", "needs tube_law.offset_free: true");
  }
  expect_error(load_with("  penalty: 0\n", "  penalty: -2\n"), "soft_constraints.penalty", "out of range");
  expect_error(load_with("  enabled: true\n", "  enabled: yes\n"), "soft_constraints.enabled", "expected true or false");
  expect_error(load_with("  lqr_input_scale: [1, 1, 100, 100]", "  lqr_input_scale: [1, 1, 0, 100]"),
               "synthesis.lqr_input_scale", "must be positive");
}

// tube_law.revert_beyond / revert_within (runtime/tube_controller.hpp): the shipped
// values are read, 0 turns the reversion off, and a bound that cannot work is refused
// naming the key.
TEST(Config, TheRevertBoundsAreReadAndChecked) {
  const Config c = load_config_from_string(default_text(), "ok.yaml");
  EXPECT_DOUBLE_EQ(c.tube_law.revert_beyond, 4.0);
  EXPECT_DOUBLE_EQ(c.tube_law.revert_within, 1.5);
  EXPECT_EQ(load_with("revert_beyond: 4.0", "revert_beyond: 0"), "");
  expect_error(load_with("revert_beyond: 4.0", "revert_beyond: 0.8"), "tube_law.revert_beyond", "above 1");
  expect_error(load_with("revert_beyond: 4.0", "revert_beyond: -2"), "tube_law.revert_beyond", "out of range");
  expect_error(load_with("revert_within: 1.5", "revert_within: 0.5"), "tube_law.revert_within", "out of range");
  expect_error(load_with("revert_within: 1.5", "revert_within: 6"), "tube_law.revert_within", "above revert_beyond");
}

}  // namespace
}  // namespace tmpc
