// Config loading: the default file loads, and every class of malformed input is an
// error that names the file and the key.
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
  ASSERT_EQ(c.disturbances.size(), 3u);
  EXPECT_DOUBLE_EQ(c.disturbances[1].time, 40.0);
  EXPECT_DOUBLE_EQ(c.disturbances[1].force.y(), 1.0);
  EXPECT_EQ(c.perturbation.runs, 10);
  EXPECT_DOUBLE_EQ(c.solver.admm_eta, 0.999);
  EXPECT_EQ(c.vehicle.rotor_inertia_reference, RotorInertiaReference::Com);
  EXPECT_EQ(c.error_model.discretization, Discretization::Zoh);
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
  expect_error(load_with("z_offset: 4.0", "z_offset: .inf"), "reference.z_offset", "finite");
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
  expect_error(load_with("mass: 1.7068", "mass: -1.7068"), "vehicle.body.mass", "positive");
}

TEST(Config, MissingKeyWrongTypeAndBadEnumAreNamed) {
  expect_error(load_with("  rod_length: 0.5", "  # rod_length: 0.5"), "vehicle.rod_length", "missing");
  expect_error(load_with("radius: 5.0", "radius: five"), "reference.radius", "expected a number");
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

}  // namespace
}  // namespace tmpc
