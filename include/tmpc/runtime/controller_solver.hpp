// The solver the runtime flies, by name: every QP solver (solvers/solver.hpp, the
// CUDA ones once registered) and the explicit law ("explicit", its file checked
// against the artifact), in the tube law's form.
#pragma once

#include <memory>
#include <string>

#include "tmpc/solvers/solver.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

/// `offset_free`: the QP around the disturbance's steady state (artifact.qp(true));
/// the explicit law, a partition over the nominal state only, refuses it. With the
/// artifact's soft constraints on (soft_penalty > 0), a QP certified infeasible, or
/// whose solve ends in a numerical failure, is solved again in the softened form (exact
/// L1 penalty on the state constraints, inputs hard; parametric_qp.hpp) instead of
/// ending in the LQR fallback: by `name` when it solves that form (active-set, admm,
/// reference), else by active-set. The law is the softened QP's solution every period,
/// continuous in the state: the hard QP's wherever the penalty covers its multipliers
/// (per state, summed over the horizon), so the softened QP is solved only where it
/// differs: an infeasible hard QP, a numerical failure, or a feasible one near its
/// boundary whose multipliers pass the penalty (the penalty is calibrated well inside
/// the feasible set, soft_penalty.hpp; there the hard solution is extreme and the
/// softened one takes a little slack instead: in the 1.5 N gust flight the servo rates'
/// peak fell from 2.82 to 0.92 times their bound). Once softened, the softened QP flies
/// each period until its solution uses no slack (then it is the hard QP's optimum).
/// Throws std::invalid_argument for an unknown name or a bad file.
std::unique_ptr<QpSolver> make_controller_solver(const std::string& name, const ControllerArtifact& a,
                                                 const SolverOptions& options, const std::string& explicit_path,
                                                 bool offset_free = false);

}  // namespace tmpc
