// The penalty of the softened QP (qp/parametric_qp.hpp) from the hard QP's multipliers.
// The L1 penalty rho 1's is exact, i.e. the softened QP has the hard QP's solution and
// no slack wherever the hard QP is feasible, when rho exceeds every dual multiplier of
// the slack's constraints: with one slack per state shared by the horizon, the sum over
// the N stages of that state's multipliers (Fletcher, Practical Methods of
// Optimization, Theorem 14.3.1). Sampled offline: parameters on rays from the origin in
// random directions, at 0.1, 0.2 and 0.3 of where the hard QP turns infeasible, solved
// exactly (the reference solver); rho = safety x the largest sum seen. The sums grow
// without bound towards the boundary (case study: 20 at 0.3, 2.4e3 at 0.9, 2.3e4 at
// 0.99), and a penalty exact that far out makes the L1 term dominate the cost where the
// QP is infeasible: with rho = 155 to 2.3e5 the 0.24 s horizon chose inputs that cut
// the immediate violation and a sustained 3 N force on the load diverged (rho = 100:
// bounded). Near the boundary the runtime flies the softened QP's solution, which takes
// a little slack there instead of the hard QP's extreme inputs: it solves the softened
// QP where the hard one is infeasible or its multiplier sums pass rho
// (runtime/controller_solver.hpp).
#pragma once

#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct SoftPenaltyCalibration {
  double largest_multiplier_sum = 0.0;  ///< max over samples and states of sum_k |y_k,i|
  double penalty = 0.0;                 ///< safety x that (and at least 1)
  int samples = 0;                      ///< feasible QPs solved
  int worst_state = -1;
};

/// Samples `directions` rays of the artifact's QP (offset-free form when its tube law
/// is; the disturbance parts of the parameter at zero).
SoftPenaltyCalibration calibrate_soft_penalty(const ControllerArtifact& a, double safety, int directions = 60,
                                              unsigned seed = 1);

/// For an artifact with soft constraints enabled and no configured penalty: sets
/// a.soft_penalty from calibrate_soft_penalty with this safety factor (the config's
/// soft_constraints.safety_factor). Does nothing otherwise; returns the calibration
/// (penalty 0 when nothing was done).
SoftPenaltyCalibration apply_soft_penalty(ControllerArtifact& a, double safety);

/// The largest over the n states of sum_k |y(first + k n + i)|, k < N: a hard QP's
/// state-constraint multipliers (rows first.. , stage by stage) summed over the horizon
/// per state, the quantity the penalty must cover; `worst` (if given) the state. No
/// allocation.
double largest_multiplier_sum(const Eigen::VectorXd& y, int first, int N, int n, int* worst = nullptr);

}  // namespace tmpc
