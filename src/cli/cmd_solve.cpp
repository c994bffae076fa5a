// tmpc solve --controller FILE.tmpc --solver NAME --x0 "..." [--json] [--eps E]: one
// nominal QP, with the KKT residuals of the returned point; with the artifact's soft
// constraints, where the softened QP's solution differs from the hard one (a QP
// certified infeasible, or one whose multipliers pass the penalty near its feasibility
// boundary) that solution and its largest slack are printed, as the controller flies it.
// tmpc solve --controller FILE.tmpc --solver NAME --batch FILE [--out CSV]: many QPs
// at once (the GPU solvers in one launch), one CSV row each.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/runtime/controller_solver.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/solver.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/design.hpp"

namespace tmpc::cli {

Eigen::VectorXd parse_vector(const std::string& s, int n, const std::string& what);  // cmd_design.cpp

namespace {

struct SolveOptionsCli {
  std::string controller, solver = "active-set", x0, explicit_law, batch, out;
  bool json = false;
  double eps = 1e-3;
};

/// Batch file: one state a line, n comma- or space-separated numbers; '#' comments.
std::vector<Eigen::VectorXd> read_batch(const std::string& path, int n) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("--batch: cannot read '" + path + "'");
  std::vector<Eigen::VectorXd> xs;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    for (char& c : line) {
      if (c == ' ' || c == '\t') c = ',';
    }
    std::string compact;  // runs of separators become one comma
    for (char c : line) {
      if (c != ',' || (!compact.empty() && compact.back() != ',')) compact += c;
    }
    if (!compact.empty() && compact.back() == ',') compact.pop_back();
    if (compact.empty()) continue;
    xs.push_back(parse_vector(compact, n, path + ":" + std::to_string(line_no)));
  }
  if (xs.empty()) throw std::runtime_error("--batch: '" + path + "' holds no states");
  return xs;
}

/// The QP's parameter for a nominal state: with the input-rate weight, the previous
/// input v_prev = 0 (the steady input) after it (qp/mpc_qp.hpp).
Eigen::VectorXd parameter_of(const Eigen::VectorXd& x0, int parameters) {
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(parameters);
  theta.head(x0.size()) = x0;
  return theta;
}

void run_batch(const SolveOptionsCli& o, const ControllerArtifact& a) {
  if (o.solver == "explicit") throw std::runtime_error("--batch: use a QP solver, not explicit");
  const MpcQpData d = a.qp();
  std::vector<Eigen::VectorXd> xs = read_batch(o.batch, a.n);
  for (Eigen::VectorXd& x : xs) x = parameter_of(x, d.parameters());
  SolverOptions opt;
  opt.eps_abs = opt.eps_rel = o.eps;
  opt.warm_start = false;
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<SolveResult> rs = solve_batch(o.solver, d, opt, xs);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ofstream file;
  if (!o.out.empty()) {
    file.open(o.out);
    if (!file) throw std::runtime_error("--out: cannot write '" + o.out + "'");
  }
  std::ostream& out = o.out.empty() ? std::cout : file;
  out << "index,status,iterations,primal_residual,dual_residual,objective,u0,u1,u2,u3\n";
  int converged = 0;
  for (std::size_t i = 0; i < rs.size(); ++i) {
    const SolveResult& r = rs[i];
    converged += r.status == SolveStatus::Converged;
    char row[512];
    std::snprintf(row, sizeof row, "%zu,%s,%d,%.6e,%.6e,%.9g,%.9g,%.9g,%.9g,%.9g\n", i, to_string(r.status), r.iterations,
                  r.primal_residual, r.dual_residual, r.objective, r.z(0), r.z(1), r.z(2), r.z(3));
    out << row;
  }
  std::fprintf(stderr, "%s: %zu QPs in %.3f s (%.0f QPs/s, set-up included), %d converged\n", o.solver.c_str(), rs.size(), s,
               static_cast<double>(rs.size()) / s, converged);
}

void run_solve(const SolveOptionsCli& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  if (!o.batch.empty()) {
    run_batch(o, a);
    return;
  }
  if (o.x0.empty()) throw std::runtime_error("solve: give --x0 (one state) or --batch FILE (many)");
  const Eigen::VectorXd state = parse_vector(o.x0, a.n, "--x0");
  SolverOptions opt;
  opt.eps_abs = opt.eps_rel = o.eps;
  opt.warm_start = false;
  auto solver = make_controller_solver(o.solver, a, opt,
                                      o.explicit_law.empty() ? explicit_path_for(o.controller) : o.explicit_law);
  const Eigen::VectorXd x0 = parameter_of(state, solver->problem().nx());
  const SolveResult r = solver->solve(x0);
  // The artifact's soft constraints: r is the softened QP's solution, which uses a slack
  // (controller_solver.hpp); the hard QP's KKT test does not apply.
  const std::string slack_state =
      r.softened && r.slack_state >= 0 && r.slack_state < static_cast<int>(a.state_names.size())
          ? a.state_names[static_cast<std::size_t>(r.slack_state)]
          : std::string();
  KktResiduals k;  // of the hard QP, where it has a solution
  if (!r.softened) {
    const CondensedQp qp = solver->problem().instance(x0);
    const Eigen::VectorXd y = solver_has_multipliers(o.solver) ? r.y : estimate_multipliers(qp, r.z, 10.0 * o.eps);
    k = kkt_residuals(qp, r.z, y);
  }
  const Eigen::Vector4d u0 = r.u0();
  const Eigen::Vector4d u0_phys = u0.cwiseQuotient(a.N_u);
  if (o.json) {
    nlohmann::json j = {{"solver", o.solver},
                        {"status", r.softened && !r.hard_solved ? "infeasible" : to_string(r.status)},
                        {"softened", r.softened},
                        {"iterations", r.iterations},
                        {"primal_residual", r.primal_residual},
                        {"dual_residual", r.dual_residual},
                        {"objective", r.objective},
                        {"solve_us", r.solve_us},
                        {"u_bar0", std::vector<double>(u0.data(), u0.data() + 4)},
                        {"u_bar0_physical", std::vector<double>(u0_phys.data(), u0_phys.data() + 4)},
                        {"z", std::vector<double>(r.z.data(), r.z.data() + r.z.size())}};
    if (r.softened) {
      j["softened_qp"] = {{"status", to_string(r.status)}, {"slack_max", r.slack_max}, {"slack_state", slack_state}};
    } else {
      j["kkt"] = {{"stationarity", k.stationarity}, {"primal", k.primal}, {"complementarity", k.complementarity},
                  {"dual_sign", k.dual_sign}, {"multipliers", solver_has_multipliers(o.solver) ? "solver" : "estimated"}};
    }
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  if (r.softened) {
    std::printf("%s: %s; the softened QP (state constraints with the exact L1 penalty, inputs "
                "hard): %s after %d iterations (%.1f us in all), largest slack %.4g (normalized) in %s\n",
                o.solver.c_str(),
                r.hard_solved ? "the hard QP's multipliers pass the penalty (near its feasibility boundary)"
                              : "infeasible (the hard QP)",
                to_string(r.status), r.iterations, r.solve_us, r.slack_max, slack_state.c_str());
  } else {
    std::printf("%s: %s after %d iterations (%.1f us), residuals primal %.3e dual %.3e\n", o.solver.c_str(),
                to_string(r.status), r.iterations, r.solve_us, r.primal_residual, r.dual_residual);
  }
  std::printf("objective %.9g\n", r.objective);
  std::printf("u_bar(0) normalized: %.6f %.6f %.6f %.6f\n", u0(0), u0(1), u0(2), u0(3));
  std::printf("u_bar(0) physical:   %.6f N, %.6f N, %.6f N m, %.6f N m\n", u0_phys(0), u0_phys(1), u0_phys(2), u0_phys(3));
  if (r.softened) return;  // the hard QP's optimality test does not apply
  std::printf("KKT (%s multipliers): stationarity %.3e, primal %.3e, complementarity %.3e, dual sign %.3e\n",
              solver_has_multipliers(o.solver) ? "solver's" : "estimated", k.stationarity, k.primal, k.complementarity,
              k.dual_sign);
}

}  // namespace

std::vector<std::string> solver_choices() {
  std::vector<std::string> names = solver_names();
  names.push_back("explicit");
  return names;
}

std::string solver_choices_help() {
  std::string help;
  for (const std::string& n : solver_choices()) help += (help.empty() ? "" : " | ") + n;
  return help;
}

void register_solve(CLI::App& app) {
  auto o = std::make_shared<SolveOptionsCli>();
  CLI::App* sub = app.add_subcommand("solve", "Solve the nominal QP for one state");
  sub->add_option("--controller", o->controller, "controller artifact")->required();
  sub->add_option("--solver", o->solver, solver_choices_help())->check(CLI::IsMember(solver_choices()));
  sub->add_option("--explicit", o->explicit_law, "explicit law for --solver explicit (default: CONTROLLER + 'x')");
  sub->add_option("--x0", o->x0, "normalized nominal state, 24 comma-separated values");
  sub->add_option("--batch", o->batch, "file of states, one a line (comma or space separated): solve them all at once");
  sub->add_option("--out", o->out, "with --batch: CSV file for the results (default: standard output)");
  sub->add_option("--eps", o->eps, "tolerance (ADMM)")->check(CLI::PositiveNumber);
  sub->add_flag("--json", o->json, "print JSON");
  sub->callback([o]() { run_solve(*o); });
}

}  // namespace tmpc::cli
