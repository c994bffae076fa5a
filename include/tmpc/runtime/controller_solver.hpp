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
/// reference), else by active-set. Where the hard QP is feasible the softened one has
/// the same solution, so it is solved only when needed and loses nothing where the
/// hard solve failed on a feasible QP. Once softened, the softened QP flies each period
/// until its solution uses no slack (then it is the hard QP's optimum): the law stays
/// continuous where the hard QP becomes feasible again, instead of jumping to the hard
/// solution at its feasibility boundary. Throws std::invalid_argument for an unknown name
/// or a bad file.
std::unique_ptr<QpSolver> make_controller_solver(const std::string& name, const ControllerArtifact& a,
                                                 const SolverOptions& options, const std::string& explicit_path,
                                                 bool offset_free = false);

}  // namespace tmpc
