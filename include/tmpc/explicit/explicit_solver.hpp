// The explicit law behind the QpSolver interface: solve(x0) locates x0 (search tree by
// default, or the thesis' scan) and evaluates the region's affine law. Status
// Infeasible when x0 is outside the partition, so the runtime falls back.
#pragma once

#include <memory>
#include <string>

#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {

enum class Locator { Tree, Scan };

/// The QP data come from the artifact at the law's horizon (for problem() and KKT checks).
std::unique_ptr<QpSolver> make_explicit_solver(const ControllerArtifact& a, ExplicitLaw law,
                                               Locator locator = Locator::Tree, int scan_threads = 1);

}  // namespace tmpc
