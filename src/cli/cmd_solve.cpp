// tmpc solve --controller FILE.tmpc --solver admm|admm-thesis|cz|reference|explicit --x0 "..." [--json]
// [--cold] [--eps E]: one nominal QP, with the KKT residuals of the returned point.
#include <cstdio>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/solver.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/design.hpp"

namespace tmpc::cli {

Eigen::VectorXd parse_vector(const std::string& s, int n, const std::string& what);  // cmd_design.cpp

namespace {

struct SolveOptionsCli {
  std::string controller, solver = "admm", x0, explicit_law;
  bool json = false;
  double eps = 1e-3;
};

void run_solve(const SolveOptionsCli& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  const Eigen::VectorXd x0 = parse_vector(o.x0, a.n, "--x0");
  SolverOptions opt;
  opt.eps_abs = opt.eps_rel = o.eps;
  opt.warm_start = false;
  auto solver = make_controller_solver(o.solver, a, opt,
                                      o.explicit_law.empty() ? explicit_path_for(o.controller) : o.explicit_law);
  const SolveResult r = solver->solve(x0);
  const CondensedQp qp = solver->problem().instance(x0);
  const Eigen::VectorXd y = solver_has_multipliers(o.solver) ? r.y : estimate_multipliers(qp, r.z, 10.0 * o.eps);
  const KktResiduals k = kkt_residuals(qp, r.z, y);
  const Eigen::Vector4d u0 = r.u0();
  const Eigen::Vector4d u0_phys = u0.cwiseQuotient(a.N_u);
  if (o.json) {
    nlohmann::json j = {{"solver", o.solver},
                        {"status", to_string(r.status)},
                        {"iterations", r.iterations},
                        {"primal_residual", r.primal_residual},
                        {"dual_residual", r.dual_residual},
                        {"objective", r.objective},
                        {"solve_us", r.solve_us},
                        {"u_bar0", std::vector<double>(u0.data(), u0.data() + 4)},
                        {"u_bar0_physical", std::vector<double>(u0_phys.data(), u0_phys.data() + 4)},
                        {"z", std::vector<double>(r.z.data(), r.z.data() + r.z.size())},
                        {"kkt", {{"stationarity", k.stationarity}, {"primal", k.primal},
                                 {"complementarity", k.complementarity}, {"dual_sign", k.dual_sign},
                                 {"multipliers", solver_has_multipliers(o.solver) ? "solver" : "estimated"}}}};
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("%s: %s after %d iterations (%.1f us), residuals primal %.3e dual %.3e\n", o.solver.c_str(),
              to_string(r.status), r.iterations, r.solve_us, r.primal_residual, r.dual_residual);
  std::printf("objective %.9g\n", r.objective);
  std::printf("u_bar(0) normalized: %.6f %.6f %.6f %.6f\n", u0(0), u0(1), u0(2), u0(3));
  std::printf("u_bar(0) physical:   %.6f N, %.6f N, %.6f N m, %.6f N m\n", u0_phys(0), u0_phys(1), u0_phys(2), u0_phys(3));
  std::printf("KKT (%s multipliers): stationarity %.3e, primal %.3e, complementarity %.3e, dual sign %.3e\n",
              solver_has_multipliers(o.solver) ? "solver's" : "estimated", k.stationarity, k.primal, k.complementarity,
              k.dual_sign);
}

}  // namespace

void register_solve(CLI::App& app) {
  auto o = std::make_shared<SolveOptionsCli>();
  CLI::App* sub = app.add_subcommand("solve", "Solve the nominal QP for one state");
  sub->add_option("--controller", o->controller, "controller artifact")->required();
  sub->add_option("--solver", o->solver, "admm | admm-thesis | cz | reference | explicit")
      ->check(CLI::IsMember({"admm", "admm-thesis", "cz", "reference", "explicit"}));
  sub->add_option("--explicit", o->explicit_law, "explicit law for --solver explicit (default: CONTROLLER + 'x')");
  sub->add_option("--x0", o->x0, "normalized nominal state, 24 comma-separated values")->required();
  sub->add_option("--eps", o->eps, "tolerance (ADMM)")->check(CLI::PositiveNumber);
  sub->add_flag("--json", o->json, "print JSON");
  sub->callback([o]() { run_solve(*o); });
}

}  // namespace tmpc::cli
