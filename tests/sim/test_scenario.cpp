// Scenario files: the shipped ones load with their documented contents, every key is
// checked (unknown keys, bad values, a bad CSV) with the file and key named, relative
// CSV paths resolve against the scenario, and a run's plant vehicle is the configured
// one scaled by the explicit factors, then by the Monte Carlo draw.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "../model/test_support.hpp"
#include "tmpc/model/perturbation.hpp"
#include "tmpc/sim/scenario.hpp"

namespace tmpc {
namespace {

std::string scenario_dir() { return test::source_dir() + "/config/scenarios/"; }

std::string error_of(const std::string& yaml, const std::string& base = "") {
  try {
    scenario_from_string(yaml, "s.yaml", base);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(accepted)";
}

const char* kHover = "duration: 10\ntrajectory: {type: hover, position: [0, 0, 2]}\n";

TEST(Scenario, TheThesisMissionIsTheDefaultScenario) {
  const Scenario s = load_scenario(scenario_dir() + "thesis_helix.yaml");
  EXPECT_EQ(s.name, "thesis_helix");
  EXPECT_DOUBLE_EQ(s.duration, 80.0);
  EXPECT_EQ(s.disturbances.event_times(), (std::vector<double>{20.0, 40.0, 60.0}));
  EXPECT_EQ(s.disturbances.load_force(70.0), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(s.plant.model, "el");
  EXPECT_DOUBLE_EQ(s.plant.random.fraction, 0.10);
  EXPECT_EQ(s.plant.random.runs, 10);
  EXPECT_FALSE(s.noise.any());
  // Its trajectory is the thesis' helix, point for point.
  for (double t : {0.0, 17.0, 55.5}) {
    EXPECT_LT((s.trajectory->at(t).p - test::thesis_helix()->at(t).p).norm(), 1e-12);
  }
}

TEST(Scenario, EveryShippedScenarioLoads) {
  for (const char* name : {"thesis_helix", "figure_eight", "waypoints", "lissajous_csv", "gusts", "noisy_sensors",
                           "mass_spring_steps"}) {
    SCOPED_TRACE(name);
    const Scenario s = load_scenario(scenario_dir() + name + ".yaml");
    EXPECT_EQ(s.name, name);
    EXPECT_GT(s.duration, 0.0);
    EXPECT_LE(s.duration, s.trajectory->duration());
  }
  const Scenario noisy = load_scenario(scenario_dir() + "noisy_sensors.yaml");
  EXPECT_TRUE(noisy.noise.any());
  EXPECT_DOUBLE_EQ(noisy.noise.white[static_cast<std::size_t>(StateGroup::Angle)], 0.00524);
  const Scenario gusts = load_scenario(scenario_dir() + "gusts.yaml");
  EXPECT_EQ(gusts.disturbances.events().back().kind, DisturbanceEvent::Kind::Gust);
  EXPECT_GT((gusts.disturbances.load_force(30.0) - Eigen::Vector3d(1, 0, 0)).norm(), 0.1);  // the gust on the step
}

TEST(Scenario, AllKindsOfEventsAndTheirKeys) {
  const Scenario s = scenario_from_string(std::string(kHover) + R"(
start_offset: {position: [0.1, 0, 0], yaw: 0.05}
disturbances:
  - {type: step, time: 1, force: [1, 0, 0], on: body}
  - {type: ramp, start: 2, end: 4, force: [0, 1, 0]}
  - {type: sine, start: 0, end: 8, amplitude: [0, 0, 0.2], frequency: 0.5, phase: 0.1}
  - {type: gust, magnitude: 1.5, time_constant: 1, redraw: 8, seed: 3, horizontal: true, on: body}
noise: {seed: 9, position: {white: 0.005, bias: 0.01, outlier: {size: 0.3, probability: 0.002}}, angular_rate: {white: 0.02}}
faults:
  - {type: efficiency, input: 0, factor: 0.85, start: 3}
  - {type: bias, input: 2, value: -0.003, start: 4, end: 6}
  - {type: stuck, input: 3, start: 7}
plant: {model: mujoco, scale: {body_mass: 1.2, rotor_inertia: 0.8}}
)", "s.yaml");
  EXPECT_EQ(s.name, "s");  // from the file name
  EXPECT_EQ(s.start_position_offset, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_DOUBLE_EQ(s.start_yaw_offset, 0.05);
  ASSERT_EQ(s.disturbances.events().size(), 4u);
  EXPECT_EQ(s.disturbances.events()[0].target, DisturbanceEvent::Target::Body);
  EXPECT_NEAR(s.disturbances.load_force(3.0).y(), 0.5, 1e-12);  // the ramp half-way
  EXPECT_NEAR(s.disturbances.load_force(5.0).y(), 1.0, 1e-12);
  EXPECT_TRUE(s.disturbances.events()[3].horizontal);
  EXPECT_DOUBLE_EQ(s.noise.bias[static_cast<std::size_t>(StateGroup::Position)], 0.01);
  EXPECT_EQ(s.noise.seed, 9u);
  EXPECT_DOUBLE_EQ(s.noise.outlier[static_cast<std::size_t>(StateGroup::Position)], 0.3);
  EXPECT_DOUBLE_EQ(s.noise.outlier_probability[static_cast<std::size_t>(StateGroup::Position)], 0.002);
  EXPECT_EQ(s.noise.outlier[static_cast<std::size_t>(StateGroup::AngularRate)], 0.0);
  ASSERT_EQ(s.faults.size(), 3u);
  EXPECT_EQ(s.faults[0].kind, ActuatorFault::Kind::Efficiency);
  EXPECT_DOUBLE_EQ(s.faults[0].factor, 0.85);
  EXPECT_TRUE(std::isinf(s.faults[0].end));
  EXPECT_EQ(s.faults[1].kind, ActuatorFault::Kind::Bias);
  EXPECT_DOUBLE_EQ(s.faults[1].value, -0.003);
  EXPECT_DOUBLE_EQ(s.faults[1].end, 6.0);
  EXPECT_EQ(s.faults[2].kind, ActuatorFault::Kind::Stuck);
  EXPECT_EQ(s.faults[2].input, 3);
  EXPECT_DOUBLE_EQ(s.faults[2].start, 7.0);
  EXPECT_EQ(s.plant.model, "mujoco");
  // The vehicle of a run: the explicit factors, then the Monte Carlo draw on top.
  const VehicleParams& v = test::default_config().vehicle;
  EXPECT_DOUBLE_EQ(s.plant_vehicle(v).body_mass, 1.2 * v.body_mass);
  EXPECT_DOUBLE_EQ(s.plant_vehicle(v).load_mass, v.load_mass);
  Scenario mc = s;
  mc.plant.random = {0.1, "uniform", 5, 10};
  const MassScaling draw = draw_mass_scaling(mc.plant.random, 2);
  EXPECT_DOUBLE_EQ(mc.plant_vehicle(v, 2).body_mass, 1.2 * v.body_mass * draw.body_mass);
  Scenario mc6 = mc;
  mc6.plant.random.seed = 6;  // the seed argument overrides the scenario's
  EXPECT_DOUBLE_EQ(mc.plant_vehicle(v, 2, 6).body_mass, mc6.plant_vehicle(v, 2).body_mass);
  EXPECT_NE(mc.plant_vehicle(v, 2, 6).body_mass, mc.plant_vehicle(v, 2).body_mass);
}

TEST(Scenario, BadInputNamesTheFileAndTheKey) {
  auto expect = [](const std::string& msg, const std::string& what) {
    EXPECT_NE(msg.find("s.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << "'" << what << "' not in: " << msg;
  };
  expect(error_of(std::string(kHover) + "durration: 5\n"), "durration: unknown key");
  expect(error_of("duration: 10\ntrajectory: {type: spiral}\n"), "trajectory.type");
  expect(error_of("duration: 10\ntrajectory: {type: helix, center: [0, 0], radius: 1, z_amplitude: 0, angular_rate: 1}\n"),
         "trajectory.center");
  expect(error_of(std::string(kHover) + "disturbances:\n  - {type: step, time: 1, force: [1, 0, 0], on: wing}\n"),
         "disturbances[0].on");
  expect(error_of(std::string(kHover) + "disturbances:\n  - {type: ramp, start: 5, end: 2, force: [1, 0, 0]}\n"),
         "disturbances[0].end");
  expect(error_of(std::string(kHover) + "disturbances:\n  - {type: gust, magnitude: 1, time_constant: 0, redraw: 1}\n"),
         "disturbances[0].time_constant");
  expect(error_of(std::string(kHover) + "noise: {angle: {white: -0.1}}\n"), "noise.angle.white");
  expect(error_of(std::string(kHover) + "noise: {position: {outlier: {size: 0.3, probability: 2}}}\n"),
         "noise.position.outlier.probability");
  expect(error_of(std::string(kHover) + "noise: {position: {outlier: {size: 0.3}}}\n"), "noise.position.outlier");
  expect(error_of(std::string(kHover) + "faults:\n  - {type: jammed, input: 0}\n"), "faults[0].type");
  expect(error_of(std::string(kHover) + "faults:\n  - {type: bias, input: 0}\n"), "faults[0].value");
  expect(error_of(std::string(kHover) + "faults:\n  - {type: stuck, input: -1}\n"), "faults[0].input");
  expect(error_of(std::string(kHover) + "faults:\n  - {type: stuck, input: 0, start: 5, end: 4}\n"), "faults[0].end");
  expect(error_of(std::string(kHover) + "faults:\n  - {type: stuck, input: 0, factor: 0.5}\n"), "faults[0].factor: unknown key");
  expect(error_of(std::string(kHover) + "plant: {model: gazebo}\n"), "plant.model");
  expect(error_of(std::string(kHover) + "plant: {scale: {body_mass: 0}}\n"), "plant.scale.body_mass");
  expect(error_of("duration: 10\ntrajectory: {type: waypoints, points: [[0, 0, 1], [0, 0, 1]], max_speed: 1, "
                  "max_acceleration: 0.5}\n"),
         "point 1 repeats point 0");
}

TEST(Scenario, CsvTrajectoriesResolveAgainstTheScenarioAndNameTheirLine) {
  const std::string dir = ::testing::TempDir();
  {
    std::ofstream f(dir + "/track.csv");
    f << "t,x,y,z,psi\n0,0,0,2,0\n1,0.1,0,2,0\n2,0.2,0,2,0\n3,0.3,0,2,0\n4,0.4,0,2,0\n";
    std::ofstream g(dir + "/bad.csv");
    g << "t,x,y,z,psi\n0,0,0,2,0\n1,0.1,0,2,0\n0.5,0.2,0,2,0\n3,0.3,0,2,0\n";
  }
  const Scenario s = scenario_from_string("duration: 4\ntrajectory: {type: csv, file: track.csv}\n", "s.yaml", dir + "/");
  EXPECT_NEAR(s.trajectory->at(2.5).p.x(), 0.25, 1e-9);
  const std::string msg = error_of("duration: 3\ntrajectory: {type: csv, file: bad.csv}\n", dir + "/");
  EXPECT_NE(msg.find("trajectory.file"), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad.csv: line 4: time 0.5 is not after 1"), std::string::npos) << msg;
  EXPECT_NE(error_of("duration: 3\ntrajectory: {type: csv, file: missing.csv}\n", dir + "/").find("missing.csv"),
            std::string::npos);
  // A CSV path ends: a scenario longer than it is an error (a path at rest holds).
  EXPECT_NE(error_of("duration: 9\ntrajectory: {type: csv, file: track.csv}\n", dir + "/").find("longer than the trajectory"),
            std::string::npos);
}

}  // namespace
}  // namespace tmpc
