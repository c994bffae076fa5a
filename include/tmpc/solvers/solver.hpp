// Online QP solvers of the nominal MPC problem (thesis ch. 4), one interface:
// set up once from the controller artifact (factorizations, products, all memory),
// then solve(x0) with no allocation. Outcomes are statuses, never exceptions.
//
//   admm         exact scaled-symmetric ADMM on an OSQP-like splitting (default, E3)
//   admm-thesis  Algorithm 4.3 as written, loop condition fixed (E2)
//   cz           constrained-zonotope formulation (4.35)-(4.47), exact ADMM machinery
//   reference    dense primal-dual interior point plus active-set polish (KKT < 1e-9)
//   active-set   exact parametric dual active set (Goldfarb-Idnani on A H^-1 A', the
//                parametric maps and the redundant rows computed offline)
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/qp/parametric_qp.hpp"

namespace tmpc {

struct ControllerArtifact;

enum class SolveStatus : int {
  Converged = 0,
  MaxIterations,
  TimeBudget,
  NumericalFailure,
  InvalidInput,  ///< x0 with the wrong size or non-finite entries
  Infeasible,    ///< x0 outside the feasible set (explicit MPC: outside its partition; exact
                 ///< ADMM: a primal infeasibility certificate)
};
const char* to_string(SolveStatus s);

struct SolverOptions {
  double eps_abs = 1e-3;         ///< absolute tolerance (thesis epsilon)
  double eps_rel = 1e-3;         ///< relative tolerance (OSQP-style stopping)
  int max_iterations = 4000;
  double time_budget_us = 0.0;   ///< 0: none; checked inside the iteration loop
  bool warm_start = true;        ///< start from the previous solution shifted one step
  // ADMM family
  double rho = 0.0;              ///< penalty; 0: rho_scale times the spectral rule, at set-up
  double rho_scale = 0.1;        ///< calibration of the spectral rule (benchmark sweep: 0.1 needs
                                 ///< 4x fewer iterations than 1 on the case study, where most
                                 ///< state constraints are inactive)
  int check_every = 5;           ///< termination test every k iterations (it costs an A'y product)
  double eps_pinf = 1e-4;        ///< exact ADMM: primal infeasibility certificate tolerance
                                 ///< (OSQP's test on the change of y; 0: off)
  bool adaptive_rho = true;      ///< OSQP-style rebalancing of rho every 25 iterations (refactors, no allocation)
  double sigma = 1e-6;           ///< proximal term on z (exact variant)
  bool equilibrate = false;      ///< Ruiz scaling at set-up (measured ~6x more cold iterations on
                                 ///< the already-normalized case study: off by default)
  double r = 0.5, s = 1.0;       ///< symmetric dual step sizes (4.21), (4.23)
  bool nesterov = false;         ///< extrapolation (4.29)-(4.31) with the restart of Algorithm 4.2
                                 ///< (the thesis variant always uses it; measured slower for
                                 ///< the exact variant on the case study, see the benchmark)
  double eta = 0.999;            ///< restart factor
  bool polish = true;            ///< exact ADMM: polish the active set read from (z, y) at each
                                 ///< check (OSQP-style; accepted only if it is a KKT point):
                                 ///< admm by a dual active-set finish (Goldfarb-Idnani) from
                                 ///< that guess; cz (H singular) by the dense KKT solve once
                                 ///< the residuals are within 100x the tolerance
  int polish_steps = 30;         ///< admm: most active-set steps of one finish (bounds its
                                 ///< cost; a finish that runs out leaves ADMM iterating)
  bool crash_start = false;      ///< before iterating, try the active set of the start point
                                 ///< (cold: the unconstrained minimizer) with active-set steps
  int polish_refine = 1;         ///< cz: after a wrong guess, up to this many primal-dual
                                 ///< active-set steps from its point (0: the plain OSQP polish)
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

struct SolveResult {
  SolveStatus status = SolveStatus::NumericalFailure;
  int iterations = 0;
  double primal_residual = 0.0;
  double dual_residual = 0.0;
  double objective = 0.0;        ///< 1/2 z'Hz + f'z (without the x0-only constant)
  double solve_us = 0.0;
  int restarts = 0;              ///< Nesterov restarts (ADMM)
  int active_set_steps = 0;      ///< admm: steps of its active-set finish, over all attempts
  Eigen::VectorXd z;             ///< u_hat (normalized), preallocated
  Eigen::VectorXd y;             ///< multipliers of lo <= A z <= hi (sign: + upper, - lower)
  /// This is the softened QP's solution, which uses a slack (the runtime's law,
  /// controller_solver.hpp): its largest slack (normalized state units) and the state
  /// that has it; hard_solved: the hard QP had a solution too (its multipliers passed
  /// the penalty) rather than being infeasible or failing. Solvers of one form never
  /// set these.
  bool softened = false;
  bool hard_solved = false;
  double slack_max = 0.0;
  int slack_state = -1;
  Eigen::Vector4d u0() const { return z.head<4>(); }
};

class QpSolver {
 public:
  virtual ~QpSolver() = default;
  /// Solve for nominal state x0 (normalized); in the offset-free form x0 is the
  /// parameter (x_bar - x_s, d_hat) of problem().nx() entries. No allocation; never throws.
  virtual const SolveResult& solve(const Eigen::VectorXd& x0) = 0;
  /// Forget the warm start (the next solve is cold).
  virtual void reset() = 0;
  virtual const char* name() const = 0;
  /// The QP instance of the last solve (for KKT checks), as the polytope formulation.
  virtual const ParametricQp& problem() const = 0;
  virtual const SolverOptions& options() const = 0;
};

/// Solver by name: "admm", "admm-thesis", "cz", "reference", "active-set". Throws
/// std::invalid_argument for an unknown name or bad options.
std::unique_ptr<QpSolver> make_solver(const std::string& name, const ControllerArtifact& a, SolverOptions options = {});
/// Same from MPC problem data (tests, other problems than the artifact's).
std::unique_ptr<QpSolver> make_solver(const std::string& name, const MpcQpData& d, SolverOptions options = {});
/// The reference solver on any parametric QP (infinite bounds allowed): the oracle of
/// the explicit-MPC construction and of tests on non-MPC problems.
std::unique_ptr<QpSolver> make_reference_solver(const ParametricQp& qp, SolverOptions options = {});
/// The active-set solver on any parametric QP with a positive definite H (infinite
/// bounds allowed), optionally with rows certified redundant over a parameter domain
/// (qp/redundant_rows.hpp). Throws std::invalid_argument for an H that is not positive
/// definite or a certificate that does not fit the QP.
std::unique_ptr<QpSolver> make_active_set_solver(const ParametricQp& qp, SolverOptions options = {},
                                                 const std::vector<int>& redundant = {},
                                                 const ParameterDomain& domain = {});
/// True when the solver returns multipliers of lo <= A z <= hi (admm, reference, active-set).
bool solver_has_multipliers(const std::string& name);

/// Solvers built outside this library (the CUDA solvers "admm-cuda" and
/// "admm-cuda-thesis", cuda/cuda_qp_solver.hpp) join make_solver by registering.
using SolverMaker = std::unique_ptr<QpSolver> (*)(const MpcQpData& d, const SolverOptions& options);
/// B QPs of one controller at once; results in the order of x0s.
using BatchSolver = std::vector<SolveResult> (*)(const MpcQpData& d, const SolverOptions& options,
                                                 const std::vector<Eigen::VectorXd>& x0s);
/// Register `name` (replacing an earlier registration); batch may be nullptr.
void register_solver(const std::string& name, SolverMaker make, BatchSolver batch = nullptr);
/// Every name make_solver accepts: the built-in solvers, then the registered ones.
std::vector<std::string> solver_names();
/// B QPs at once: the solver's batched path where it has one (the GPU: one launch),
/// otherwise one solver solving them in turn (cold starts). Throws like make_solver.
std::vector<SolveResult> solve_batch(const std::string& name, const MpcQpData& d, const SolverOptions& options,
                                     const std::vector<Eigen::VectorXd>& x0s);

/// The spectral penalty rule (thesis future work): rho = 1 / sqrt(l_min l_max) over
/// the nonzero eigenvalues of A H^-1 A' (Ghadimi et al. 2015), computed offline.
double spectral_rho(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A);

}  // namespace tmpc
