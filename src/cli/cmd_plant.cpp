// Commands that run a plant:
//   tmpc openloop   --config FILE [--plant el|mujoco] [--duration S] [--disturbance] [--run K] [--out CSV]
//       feedforward along the helix, open loop; reports the drift from the reference.
//   tmpc crosscheck --config FILE [--states N] [--json]
//       MuJoCo against the Euler-Lagrange model: forward dynamics, hover, open loop.
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "data_files.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/sim/el_plant.hpp"
#include "tmpc/sim/mujoco_plant.hpp"
#include "tmpc/sim/plant_model.hpp"
#include "tmpc/sim/scenario.hpp"

namespace tmpc::cli {

namespace {

struct OpenLoopOptions {
  std::string config = "config/tiltrotor.yaml", scenario = kDefaultScenario;
  std::string plant;
  double duration = 2.0;
  bool disturbance = false;
  int run = -1;
  std::string out;
};

void run_openloop(const OpenLoopOptions& o) {
  const Config cfg = load_config(data_file(o.config));
  if (cfg.model != ModelKind::Tiltrotor) throw std::runtime_error(o.config + ": openloop flies the tiltrotor");
  Scenario sc = load_scenario(data_file(o.scenario));
  if (!o.disturbance) sc.disturbances = DisturbanceProfile{};
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator traj(model, sc.trajectory, cfg.attitude);
  const ReferencePoint r0 = traj.at(0.0);
  Eigen::VectorXd x0(kNx);
  x0 << r0.q, r0.qd;
  auto plant = make_scenario_plant(PlantModel::from_config(cfg), sc, x0, o.run, -1, o.plant);
  std::ofstream csv;
  if (!o.out.empty()) {
    csv.open(o.out);
    if (!csv) throw std::runtime_error("cannot write " + o.out);
    csv << "t";
    for (const char* n : kCoordNames) csv << "," << n;
    csv << ",x_r,y_r,z_r,f_r,f_l,tau_r,tau_l\n";
  }
  const int n = static_cast<int>(std::lround(o.duration / cfg.sample_time));
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector4d u = feedforward(model, traj.at(plant->time()));
    plant->advance(u, cfg.sample_time);
    const ReferencePoint r = traj.at(plant->time());
    worst = std::max(worst, (plant->state().head<3>() - r.q.head<3>()).norm());
    if (csv) {
      csv << plant->time();
      for (int i = 0; i < kNq; ++i) csv << "," << plant->state()(i);
      csv << "," << r.q(0) << "," << r.q(1) << "," << r.q(2);
      for (int i = 0; i < 4; ++i) csv << "," << u(i);
      csv << "\n";
    }
  }
  std::printf("plant %s, %.3g s of feedforward along %s%s%s: load within %.3e m of the reference\n",
              plant->name().c_str(), o.duration, sc.trajectory->description().c_str(),
              o.disturbance ? ", with the scenario's disturbances" : "",
              o.run >= 0 ? (", Monte Carlo run " + std::to_string(o.run)).c_str() : "", worst);
  if (!o.out.empty()) std::printf("trajectory: %s\n", o.out.c_str());
}

struct CrossCheckOptions {
  std::string config = "config/tiltrotor.yaml";
  int states = 1000;
  bool json = false;
};

#ifndef TMPC_HAVE_MUJOCO
void run_crosscheck(const CrossCheckOptions&) {
  throw std::runtime_error("crosscheck needs the MuJoCo plant: this build has none (built with TMPC_WITH_MUJOCO=OFF "
                           "or without libmujoco-dev)");
}
#else
void run_crosscheck(const CrossCheckOptions& o) {
  const Config cfg = load_config(data_file(o.config));
  const TiltrotorModel model(cfg.vehicle);
  MujocoPlant mj(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  ElPlant el(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep);
  // Forward dynamics at random admissible states and inputs.
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> pos(-5, 5), ang(-0.5, 0.5), uni(-1, 1), thrust(0, 30), torque(-2, 2);
  const double rate_box[10] = {0.6, 1.0, 0.2, 1.0, 1.0, 0.5, 2.0, 1.0, 0.2, 0.2};
  double worst = 0.0, sum = 0.0;
  for (int i = 0; i < o.states; ++i) {
    State20 x;
    x << pos(rng), pos(rng), pos(rng), ang(rng), ang(rng), 3.0 * uni(rng), ang(rng), ang(rng), ang(rng), ang(rng),
        Vec10::Zero();
    for (int j = 0; j < 10; ++j) x(10 + j) = rate_box[j] * uni(rng);
    const Eigen::Vector4d u(thrust(rng), thrust(rng), torque(rng), torque(rng));
    const Eigen::Vector3d d(uni(rng), uni(rng), uni(rng));
    const Vec10 a = model.acceleration(x.head<10>(), x.tail<10>(), u, d);
    const double e = (a - mj.acceleration(x, u, d)).norm() / a.norm();
    worst = std::max(worst, e);
    sum += e;
  }
  // Hover at the solved equilibrium.
  ReferenceGenerator traj(model, load_scenario(data_file(kDefaultScenario)).trajectory, cfg.attitude);
  const Equilibrium eq = solve_hover_equilibrium(model, cfg.envelope.yaw);
  State20 xh;
  xh << eq.q(), Vec10::Zero();
  const double hover = mj.acceleration(xh, eq.u, Eigen::Vector3d::Zero()).cwiseAbs().maxCoeff();
  // Open loop: 2 s of feedforward along the helix, 0.5 s of a servo torque step.
  auto compare = [&](const Eigen::VectorXd& x0, double duration, const std::function<Eigen::Vector4d(double)>& input) {
    el.reset(x0, 0.0);
    mj.reset(x0, 0.0);
    double dp = 0.0, da = 0.0;
    const double dt = cfg.simulation.substep;
    for (long k = 0; k < std::lround(duration / dt); ++k) {
      const Eigen::VectorXd u = input(el.time());
      el.advance(u, dt);
      mj.advance(u, dt);
      dp = std::max(dp, (el.state().head<3>() - mj.state().head<3>()).norm());
      da = std::max(da, (el.state().segment<7>(kPhi) - mj.state().segment<7>(kPhi)).cwiseAbs().maxCoeff());
    }
    return std::make_pair(dp, da);
  };
  const ReferencePoint r0 = traj.at(0.0);
  Eigen::VectorXd x0(kNx);
  x0 << r0.q, r0.qd;
  const auto helix = compare(x0, 2.0, [&](double t) { return feedforward(model, traj.at(t)); });
  const Eigen::Vector4d step = eq.u + Eigen::Vector4d(0, 0, 0.05, 0);
  const auto servo = compare(Eigen::VectorXd(xh), 0.5, [&](double) { return step; });

  if (o.json) {
    nlohmann::json j;
    j["mujoco_version"] = MujocoPlant::version();
    j["forward_dynamics"] = {{"states", o.states}, {"max_relative_error", worst}, {"mean_relative_error", sum / o.states}};
    j["hover_max_abs_acceleration"] = hover;
    j["open_loop"] = {{"helix_2s", {{"position_m", helix.first}, {"angle_rad", helix.second}}},
                      {"servo_step_0p5s", {{"position_m", servo.first}, {"angle_rad", servo.second}}}};
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("MuJoCo %s against the Euler-Lagrange model (%s)\n", MujocoPlant::version().c_str(), o.config.c_str());
  std::printf("  forward dynamics at %d random states and inputs: max relative error %.3e (mean %.3e)\n", o.states,
              worst, sum / o.states);
  std::printf("  hover at the equilibrium: max |q''| = %.3e\n", hover);
  std::printf("  open loop, helix feedforward 2 s: %.3e m, %.3e rad\n", helix.first, helix.second);
  std::printf("  open loop, servo torque step 0.5 s: %.3e m, %.3e rad\n", servo.first, servo.second);
}
#endif

}  // namespace

void register_plant(CLI::App& app) {
  auto ol = std::make_shared<OpenLoopOptions>();
  CLI::App* sub = app.add_subcommand("openloop", "Feedforward along a scenario's trajectory on a plant, open loop");
  sub->add_option("--config", ol->config, "design configuration (YAML)")->check(CLI::ExistingFile);
  sub->add_option("--scenario", ol->scenario, "the scenario whose trajectory (and plant) to fly")->check(CLI::ExistingFile);
  sub->add_option("--plant", ol->plant, "plant: el | mujoco (default: the scenario's)")
      ->check(CLI::IsMember({"el", "mujoco"}));
  sub->add_option("--duration", ol->duration, "seconds")->check(CLI::PositiveNumber);
  sub->add_flag("--disturbance", ol->disturbance, "apply the scenario's disturbances");
  sub->add_option("--run", ol->run, "Monte Carlo run index (masses and inertias perturbed)")->check(CLI::NonNegativeNumber);
  sub->add_option("--out", ol->out, "write the trajectory as CSV");
  sub->callback([ol]() { run_openloop(*ol); });

  auto cc = std::make_shared<CrossCheckOptions>();
  CLI::App* c = app.add_subcommand("crosscheck", "MuJoCo plant against the Euler-Lagrange model");
  c->add_option("--config", cc->config, "design configuration (YAML)")->check(CLI::ExistingFile);
  c->add_option("--states", cc->states, "random states for the forward-dynamics check")->check(CLI::PositiveNumber);
  c->add_flag("--json", cc->json, "print JSON");
  c->callback([cc]() { run_crosscheck(*cc); });
}

}  // namespace tmpc::cli
