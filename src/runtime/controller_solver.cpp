// The runtime's solver factory (see controller_solver.hpp).
#include "tmpc/runtime/controller_solver.hpp"

#include <stdexcept>

#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/solvers/soft_penalty.hpp"

namespace tmpc {

namespace {

/// The softened QP's solution every period, by the cheaper way: the hard QP first, and
/// the softened QP when the hard one is certified infeasible, fails numerically, or its
/// multipliers show that the softened optimum uses a slack (a state's multipliers summed
/// over the horizon above the penalty); the softened QP again each period until it uses
/// no slack (see controller_solver.hpp). Its result has the hard layout (u_hat);
/// the slacks are reported in softened, slack_max and slack_state. No allocation per
/// solve.
class SoftRecoverySolver final : public QpSolver {
 public:
  /// d: the hard MPC QP (its last N n rows the state constraints); penalty: the
  /// softened QP's rho; check_multipliers: the hard solver returns its multipliers
  /// (solver_has_multipliers).
  SoftRecoverySolver(std::unique_ptr<QpSolver> hard, std::unique_ptr<QpSolver> soft, const MpcQpData& d,
                     double penalty, bool check_multipliers)
      : hard_(std::move(hard)), soft_(std::move(soft)), check_multipliers_(check_multipliers), penalty_(penalty) {
    res_.z = Eigen::VectorXd::Zero(hard_->problem().nz());
    res_.y = Eigen::VectorXd::Zero(hard_->problem().nc());
    slacks_ = soft_->problem().slacks;
    stages_ = d.N;
    state_row0_ = hard_->problem().nc() - d.N * d.n;
  }
  const SolveResult& solve(const Eigen::VectorXd& x0) override {
    int h_iterations = 0, h_steps = 0;
    double h_us = 0.0;
    const SolveResult* solved = nullptr;  // the hard QP's solution, where it has one
    if (!stay_soft_) {
      const SolveResult& h = hard_->solve(x0);
      // Infeasible, or a numerical failure (e.g. a nearly infeasible QP whose Farkas ray
      // the active set cannot certify), or feasible but with multipliers past the
      // penalty: near the hard QP's feasibility boundary its solution is extreme (a
      // servo rate 2.8 times its bound in a gust flight) while the softened optimum takes
      // a little slack instead. Below the penalty both have the same solution.
      if (h.status != SolveStatus::Infeasible && h.status != SolveStatus::NumericalFailure && !beyond_penalty(h)) {
        return h;
      }
      if (h.status == SolveStatus::Converged) solved = &h;
      h_iterations = h.iterations;
      h_steps = h.active_set_steps;
      h_us = h.solve_us;
    }
    const SolveResult& r = soft_->solve(x0);
    if (solved != nullptr && r.status != SolveStatus::Converged) return *solved;  // the hard QP's, rather than none
    res_.status = r.status;
    res_.iterations = h_iterations + r.iterations;
    res_.solve_us = h_us + r.solve_us;
    res_.primal_residual = r.primal_residual;
    res_.dual_residual = r.dual_residual;
    res_.objective = r.objective;
    res_.restarts = r.restarts;
    res_.active_set_steps = h_steps + r.active_set_steps;
    res_.z = r.z.head(res_.z.size());
    res_.y.setZero();  // no multipliers of the hard QP: its solution is not the one flown
    res_.softened = true;
    res_.hard_solved = solved != nullptr;
    Eigen::Index worst = 0;
    res_.slack_max = slacks_ > 0 ? r.z.tail(slacks_).maxCoeff(&worst) : 0.0;
    res_.slack_state = static_cast<int>(worst);
    // Back to the hard QP only once the softened one uses no slack: there its solution is
    // the hard QP's optimum (a hard-feasible point of the same cost), so the law stays
    // continuous. Going back as soon as the hard QP is feasible again jumped from the
    // softened solution to the hard one at its feasibility boundary, where that one is
    // extreme (the gust flight: thrusts 11 N to 8.7 and 14.4 N in two periods, servo rates
    // past their bounds; README "Soft state constraints").
    stay_soft_ = r.status == SolveStatus::Converged && res_.slack_max > kSlackZero;
    return res_;
  }
  /// Whether the softened QP's solution differs from this hard one: (z, s = 0) is the
  /// softened optimum iff, per state i, rho - sum_k |y_k,i| >= 0 (the slack's
  /// multiplier; soft_penalty.hpp). Only for solvers that return multipliers
  /// (solver_has_multipliers: admm, reference, active-set); the explicit law flies its
  /// hard solution wherever it has one.
  bool beyond_penalty(const SolveResult& h) const {
    if (!check_multipliers_ || h.status != SolveStatus::Converged || h.y.size() != hard_->problem().nc()) return false;
    return largest_multiplier_sum(h.y, state_row0_, stages_, slacks_) > penalty_;
  }
  void reset() override {
    stay_soft_ = false;
    hard_->reset();
    soft_->reset();
  }
  const char* name() const override { return hard_->name(); }
  const ParametricQp& problem() const override { return hard_->problem(); }
  const SolverOptions& options() const override { return hard_->options(); }

 private:
  static constexpr double kSlackZero = 1e-9;  ///< a slack at most this (normalized) is none
  std::unique_ptr<QpSolver> hard_, soft_;
  bool check_multipliers_ = false;
  double penalty_ = 0.0;
  bool stay_soft_ = false;
  SolveResult res_;
  int slacks_ = 0, stages_ = 0, state_row0_ = 0;
};

}  // namespace

std::unique_ptr<QpSolver> make_controller_solver(const std::string& name, const ControllerArtifact& a,
                                                 const SolverOptions& options, const std::string& explicit_path,
                                                 bool offset_free) {
  std::unique_ptr<QpSolver> hard;
  if (name != "explicit") {
    hard = make_solver(name, a.qp(offset_free), options);
  } else {
    if (offset_free) {
      throw std::invalid_argument("solver 'explicit' has no offset-free form (its regions partition the nominal state "
                                  "only): fly it with --tube-law mayne, or use an online solver");
    }
    if (a.rate_weighted()) {
      throw std::invalid_argument("solver 'explicit' does not solve the input-rate-weighted QP (weights.input_rate): "
                                  "use an online solver");
    }
    if (explicit_path.empty()) throw std::invalid_argument("solver 'explicit' needs the explicit law's file (tmpc explicit)");
    hard = make_explicit_solver(a, load_explicit(explicit_path, &a));
  }
  if (!(a.soft_penalty > 0.0)) return hard;
  const std::string soft_name = name == "admm" || name == "reference" || name == "active-set" ? name : "active-set";
  SolverOptions soft = options;
  if (soft_name == "admm" && soft.rho <= 0.0) {
    // The hard QP's penalty: the spectral rule on the softened QP sees the slacks' tiny
    // curvature (1e-8 of H) and gives a penalty orders of magnitude too small.
    const ParametricQp hard_qp = ParametricQp::from_mpc(a.qp(offset_free));
    soft.rho = options.rho_scale * spectral_rho(hard_qp.H, hard_qp.A);
  }
  return std::make_unique<SoftRecoverySolver>(std::move(hard), make_solver(soft_name, a.qp(offset_free, true), soft),
                                              a.qp(offset_free), a.soft_penalty, solver_has_multipliers(name));
}

}  // namespace tmpc
