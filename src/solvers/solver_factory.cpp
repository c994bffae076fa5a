// make_solver(), the penalty rule, option validation.
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "parametric_active_set.hpp"
#include "solvers_internal.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

const char* to_string(SolveStatus s) {
  switch (s) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::MaxIterations: return "max-iterations";
    case SolveStatus::TimeBudget: return "time-budget";
    case SolveStatus::NumericalFailure: return "numerical-failure";
    case SolveStatus::InvalidInput: return "invalid-input";
    case SolveStatus::Infeasible: return "infeasible";
  }
  return "?";
}

void SolverOptions::validate() const {
  auto need = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("solver options: ") + what);
  };
  need(eps_abs > 0.0 && std::isfinite(eps_abs), "eps_abs must be positive");
  need(eps_rel >= 0.0 && std::isfinite(eps_rel), "eps_rel must be >= 0");
  need(max_iterations >= 1, "max_iterations must be >= 1");
  need(time_budget_us >= 0.0, "time_budget_us must be >= 0");
  need(rho >= 0.0 && std::isfinite(rho), "rho must be >= 0 (0: spectral rule)");
  need(sigma >= 0.0, "sigma must be >= 0");
  need(rho_scale > 0.0 && std::isfinite(rho_scale), "rho_scale must be positive");
  need(check_every >= 1, "check_every must be >= 1");
  need(polish_refine >= 0, "polish_refine must be >= 0");
  need(polish_steps >= 0, "polish_steps must be >= 0");
  need(eps_pinf >= 0.0 && std::isfinite(eps_pinf), "eps_pinf must be >= 0");
  // Convergence region of the symmetric ADMM (He et al.): r in (-1, 1), s in
  // (0, (1 + sqrt 5) / 2), r + s > 0, |r| < 1 + s - s^2.
  need(r > -1.0 && r < 1.0, "r must be in (-1, 1)");
  need(s > 0.0 && s < 0.5 * (1.0 + std::sqrt(5.0)), "s must be in (0, 1.618)");
  need(r + s > 0.0 && std::abs(r) < 1.0 + s - s * s, "(r, s) outside the symmetric ADMM convergence region");
  need(eta > 0.0 && eta < 1.0, "eta must be in (0, 1)");
}

double spectral_rho(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A) {
  // Nonzero eigenvalues of A H^-1 A' = eigenvalues of H^-1/2 A'A H^-1/2.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eh(H);
  const Eigen::MatrixXd Hmh = eh.eigenvectors() * eh.eigenvalues().cwiseInverse().cwiseSqrt().asDiagonal() *
                              eh.eigenvectors().transpose();
  const Eigen::MatrixXd M = Hmh * A.transpose() * A * Hmh;
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (M + M.transpose())).eigenvalues();
  const double lmax = ev.maxCoeff();
  double lmin = lmax;
  for (Eigen::Index i = 0; i < ev.size(); ++i) {
    if (ev(i) > 1e-12 * lmax) lmin = std::min(lmin, ev(i));
  }
  return 1.0 / std::sqrt(lmin * lmax);
}

namespace detail {
bool valid_state(const Eigen::VectorXd& x0, int n, SolveResult& res) {
  if (x0.size() == n && x0.allFinite()) return true;
  res.status = SolveStatus::InvalidInput;
  res.iterations = 0;
  res.solve_us = 0.0;
  return false;
}
}  // namespace detail

std::unique_ptr<QpSolver> make_solver(const std::string& name, const ControllerArtifact& a, SolverOptions options) {
  return make_solver(name, a.qp(), options);
}

bool solver_has_multipliers(const std::string& name) {
  return name == "admm" || name == "reference" || name == "active-set";
}

std::unique_ptr<QpSolver> make_active_set_solver(const ParametricQp& qp, SolverOptions options,
                                                 const std::vector<int>& redundant, const ParameterDomain& domain) {
  options.validate();
  return std::make_unique<detail::ParametricActiveSet>(qp, redundant, domain, options);
}

std::unique_ptr<QpSolver> make_reference_solver(const ParametricQp& qp, SolverOptions options) {
  options.validate();
  return std::make_unique<detail::ReferenceQp>(qp, options);
}

namespace {
struct Registered {
  SolverMaker make;
  BatchSolver batch;
};
std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, Registered>& registry() {
  static std::map<std::string, Registered> r;
  return r;
}
const char* const kBuiltin[] = {"admm", "admm-thesis", "cz", "reference", "active-set"};
}  // namespace

void register_solver(const std::string& name, SolverMaker make, BatchSolver batch) {
  if (make == nullptr) throw std::invalid_argument("register_solver: no maker for '" + name + "'");
  for (const char* b : kBuiltin) {
    if (name == b) throw std::invalid_argument("register_solver: '" + name + "' is a built-in solver");
  }
  std::lock_guard<std::mutex> lock(registry_mutex());
  registry()[name] = Registered{make, batch};
}

std::vector<std::string> solver_names() {
  std::vector<std::string> names(std::begin(kBuiltin), std::end(kBuiltin));
  std::lock_guard<std::mutex> lock(registry_mutex());
  for (const auto& [name, r] : registry()) names.push_back(name);
  return names;
}

std::vector<SolveResult> solve_batch(const std::string& name, const MpcQpData& d, const SolverOptions& options,
                                     const std::vector<Eigen::VectorXd>& x0s) {
  BatchSolver batch = nullptr;
  {
    std::lock_guard<std::mutex> lock(registry_mutex());
    const auto it = registry().find(name);
    if (it != registry().end()) batch = it->second.batch;
  }
  if (batch != nullptr) return batch(d, options, x0s);
  SolverOptions cold = options;
  cold.warm_start = false;
  auto solver = make_solver(name, d, cold);
  std::vector<SolveResult> out;
  out.reserve(x0s.size());
  for (const Eigen::VectorXd& x0 : x0s) out.push_back(solver->solve(x0));
  return out;
}

std::unique_ptr<QpSolver> make_solver(const std::string& name, const MpcQpData& d, SolverOptions options) {
  options.validate();
  SolverMaker registered = nullptr;
  {
    std::lock_guard<std::mutex> lock(registry_mutex());
    const auto it = registry().find(name);
    if (it != registry().end()) registered = it->second.make;
  }
  if (d.soft() && name != "admm" && name != "reference" && name != "active-set") {
    throw std::invalid_argument("solver '" + name +
                                "' does not solve the softened QP (soft state constraints); admm, active-set and "
                                "reference do");
  }
  if (d.rate_weighted() && (name == "admm-thesis" || name == "cz")) {
    throw std::invalid_argument("solver '" + name + "' does not solve the input-rate-weighted QP (weights.input_rate); "
                                "admm, active-set and reference do");
  }
  if (registered != nullptr) return registered(d, options);
  const ParametricQp qp = ParametricQp::from_mpc(d);
  if (name == "admm") return std::make_unique<detail::AdmmPolytope>(qp, d.M, d.m, d.N, d.n, options);
  if (name == "admm-thesis") return std::make_unique<detail::AdmmThesis>(d, qp, options);
  if (name == "cz") return std::make_unique<detail::AdmmCz>(d, qp, options);
  if (name == "reference") return std::make_unique<detail::ReferenceQp>(qp, options);
  if (name == "active-set") {
    // The certificate numbers the hard QP's rows; the softened QP keeps every row.
    static const std::vector<int> none;
    return std::make_unique<detail::ParametricActiveSet>(qp, d.soft() ? none : d.redundant_rows, d.domain, options);
  }
  std::string names;
  for (const std::string& n : solver_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solver '" + name + "' (available: " + names + ")");
}

}  // namespace tmpc
