// `tmpc model`: the equilibrium, u_r(0), eigenvalues of the nominal error model and
// the LPV summary, as text or JSON with stable keys; `--run K [--seed S]` of a scenario's Monte
// Carlo draw for its perturbed vehicle, `--matrices` the discrete model itself (for
// analyses outside tmpc, e.g. scripts/best_case_peak.py).
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "data_files.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/model/error_model.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/synthesis/json_rows.hpp"

namespace tmpc::cli {

namespace {

struct ModelOptions {
  std::string config = "config/tiltrotor.yaml", scenario;
  int run = -1;
  long seed = -1;
  bool json = false, matrices = false;
};

nlohmann::json eigen_json(const Eigen::VectorXcd& ev) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < ev.size(); ++i) out.push_back({ev(i).real(), ev(i).imag()});
  return out;
}

template <class V>
std::vector<double> to_vec(const V& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

void run_model(const ModelOptions& opt) {
  Config cfg = load_config(data_file(opt.config));
  if (cfg.model != ModelKind::Tiltrotor) throw std::runtime_error(opt.config + ": `tmpc model` reports the tiltrotor's model");
  if (opt.seed >= 0 && opt.run < 0) throw std::runtime_error("--seed needs --run (the seed of its Monte Carlo draws)");
  if (opt.run >= 0) {  // the vehicle of a Monte Carlo run: its equilibrium and error model
    if (opt.scenario.empty()) throw std::runtime_error("--run needs --scenario (its plant.random draws the vehicle)");
    const Scenario sc = load_scenario(data_file(opt.scenario));
    if (!(sc.plant.random.fraction > 0.0)) {
      throw std::runtime_error("--run " + std::to_string(opt.run) + ": " + opt.scenario +
                               " draws no vehicles (plant.random.fraction is 0)");
    }
    cfg.vehicle = sc.plant_vehicle(cfg.vehicle, opt.run, opt.seed);
  }
  if (opt.matrices && !opt.json) throw std::runtime_error("--matrices needs --json");
  const TiltrotorModel model(cfg.vehicle);
  const ErrorModel em = build_error_model(cfg);
  // The feedforward at the start of a scenario's trajectory (default: hover).
  std::shared_ptr<const Trajectory> traj = make_hover(HoverShape{Eigen::Vector3d::Zero(), cfg.envelope.yaw});
  if (!opt.scenario.empty()) traj = load_scenario(data_file(opt.scenario)).trajectory;
  ReferenceGenerator gen(model, traj, cfg.attitude);
  const Eigen::Vector4d ur0 = feedforward(model, gen.at(0.0));

  Eigen::EigenSolver<Eigen::MatrixXd> ec(em.A_c, false);
  Eigen::EigenSolver<Eigen::MatrixXd> ed(em.A, false);
  const Eigen::VectorXcd evc = ec.eigenvalues();
  const Eigen::VectorXcd evd = ed.eigenvalues();
  const double rho = evd.cwiseAbs().maxCoeff();
  const double max_re = evc.real().maxCoeff();
  const Equilibrium& eq = em.equilibrium;
  const char* disc = em.discretization == Discretization::Zoh ? "zoh" : "euler";

  if (opt.json) {
    nlohmann::json j;
    j["config"] = opt.config;
    j["equilibrium"] = {{"gamma_1", eq.angles(0)}, {"gamma_2", eq.angles(1)}, {"alpha_r", eq.angles(2)},
                        {"alpha_l", eq.angles(3)}, {"f_r", eq.u(0)},         {"f_l", eq.u(1)},
                        {"tau_r", eq.u(2)},        {"tau_l", eq.u(3)},       {"residual", eq.residual}};
    j["feedforward_t0"] = {{"f_r", ur0(0)}, {"f_l", ur0(1)}, {"tau_r", ur0(2)}, {"tau_l", ur0(3)}};
    j["continuous"] = {{"eigenvalues", eigen_json(evc)}, {"max_real_part", max_re}};
    j["discrete"] = {{"method", disc},
                     {"sample_time", em.sample_time},
                     {"eigenvalues", eigen_json(evd)},
                     {"spectral_radius", rho}};
    j["lpv"] = {{"vertices", em.A_vertices.size()},
                {"parameters", 3},
                {"sigma_min", to_vec(em.lpv.sigma_min)},
                {"sigma_max", to_vec(em.lpv.sigma_max)},
                {"sigma_part", em.lpv.sigma_part},
                {"affinity_residual", em.lpv.affinity_residual},
                {"affinity_residual_relative", em.lpv.affinity_residual_relative},
                {"b_variation", em.lpv.b_variation}};
    j["reference"] = {{"attitude", cfg.attitude == ReferenceAttitude::Trim ? "trim" : "equilibrium"},
                      {"feedforward_at", traj->description()}};
    j["inputs"] = {{"u_r_min", to_vec(em.u_r_min)},
                   {"u_r_max", to_vec(em.u_r_max)},
                   {"error_min", to_vec(em.input_error_min)},
                   {"error_max", to_vec(em.input_error_max)}};
    j["vehicle"] = {{"load_mass", cfg.vehicle.load_mass}, {"body_mass", cfg.vehicle.body_mass},
                    {"rotor_mass", cfg.vehicle.rotor_mass}, {"gravity", cfg.vehicle.gravity}, {"run", opt.run}};
    if (opt.matrices) {
      // x(k+1) = A x(k) + B u(k) + D d(k): the augmented error model at sigma = 0 (physical
      // units; d the force on the load, N), with the box and the actuator limits.
      j["matrices"] = {{"A", json_rows(em.A)},
                       {"B", json_rows(em.B)},
                       {"D", json_rows(em.D)},
                       {"state_names", cfg.state_names()},
                       {"state_error_max", to_vec(cfg.state_error_max)},
                       {"measured", em.measured},
                       {"u_eq", to_vec(eq.u)},
                       {"input_min", to_vec(cfg.input_min)},
                       {"input_max", to_vec(cfg.input_max)}};
    }
    std::cout << j.dump(2) << "\n";
    return;
  }

  std::printf("config: %s\n\n", opt.config.c_str());
  std::printf("hover equilibrium (psi = %.4g rad), residual %.2e after %d Gauss-Newton steps\n", cfg.envelope.yaw,
              eq.residual, eq.iterations);
  std::printf("  gamma_1 = %.6e rad   (thesis 1.3170e-4)\n", eq.angles(0));
  std::printf("  gamma_2 = %.6f rad   (thesis 0.01396)\n", eq.angles(1));
  std::printf("  alpha_r = %.6f rad   (thesis 0.0140)\n", eq.angles(2));
  std::printf("  alpha_l = %.6f rad   (thesis 0.0138)\n", eq.angles(3));
  std::printf("  f_r = %.6f N, f_l = %.6f N, tau_r = %.3e N m, tau_l = %.3e N m\n\n", eq.u(0), eq.u(1), eq.u(2),
              eq.u(3));
  std::printf("feedforward u_r(0) of %s: f_r = %.6f N, f_l = %.6f N, tau_r = %.3e N m, tau_l = %.3e N m\n\n",
              traj->description().c_str(), ur0(0), ur0(1), ur0(2), ur0(3));
  std::printf("continuous nominal A_a (24 states), eigenvalues (max real part %.3e):\n", max_re);
  for (Eigen::Index i = 0; i < evc.size(); ++i) {
    std::printf("  %+.6f %+.6fj\n", evc(i).real(), evc(i).imag());
  }
  std::printf("\ndiscrete nominal A_z (%s, T = %.4g s), spectral radius %.9f\n", disc, em.sample_time, rho);
  for (Eigen::Index i = 0; i < evd.size(); ++i) {
    std::printf("  %+.9f %+.9fj  |%.9f|\n", evd(i).real(), evd(i).imag(), std::abs(evd(i)));
  }
  std::printf("\nLPV: sigma = reference acceleration, %zu vertices\n", em.A_vertices.size());
  std::printf("  sigma in [%.4g, %.4g] x [%.4g, %.4g] x [%.4g, %.4g] m/s^2\n", em.lpv.sigma_min(0),
              em.lpv.sigma_max(0), em.lpv.sigma_min(1), em.lpv.sigma_max(1), em.lpv.sigma_min(2),
              em.lpv.sigma_max(2));
  std::printf("  max ||A_lpv(sigma) - A0|| / ||A0||          = %.3e\n", em.lpv.sigma_part);
  std::printf("  affinity residual max ||A(sigma) - A_lpv|| / ||A0|| = %.3e (%.1f%% of the variation of A)\n",
              em.lpv.affinity_residual, 100.0 * em.lpv.affinity_residual_relative);
  std::printf("  B over the envelope: max ||B(sigma) - B(0)|| / ||B(0)|| = %.3e (reference attitude: %s)\n",
              em.lpv.b_variation, cfg.attitude == ReferenceAttitude::Trim ? "trim" : "equilibrium");
  std::printf("\ninput box in error coordinates (holds over the whole envelope):\n");
  for (int i = 0; i < 4; ++i) {
    std::printf("  u_tilde[%d] in [%.4f, %.4f]\n", i, em.input_error_min(i), em.input_error_max(i));
  }
}

}  // namespace

void register_model(CLI::App& app) {
  auto opt = std::make_shared<ModelOptions>();
  CLI::App* sub = app.add_subcommand("model", "Equilibrium, feedforward and the linear error model of a config");
  sub->add_option("--config", opt->config, "design configuration (YAML)")->check(CLI::ExistingFile);
  sub->add_option("--scenario", opt->scenario, "the feedforward at this scenario's start (default: hover)")
      ->check(CLI::ExistingFile);
  sub->add_option("--run", opt->run, "the vehicle of Monte Carlo run K of --scenario's plant.random")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--seed", opt->seed, "with --run: the Monte Carlo seed (default: the scenario's plant.random.seed)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--json", opt->json, "print JSON with stable keys");
  sub->add_flag("--matrices", opt->matrices, "with --json: the discrete error model A, B, D, the box and the limits");
  sub->callback([opt]() { run_model(*opt); });
}

}  // namespace tmpc::cli
