// The QP data of the GPU solver (cuda/), built on the host in double and stored as
// float (tmpc/gpu/admm_problem.hpp), and the options it runs with. The GPU's exact
// variant is the CPU "admm" with a fixed penalty and no polish (both need a
// refactorization on the device); `cpu_twin_options` gives the CPU settings that
// compute the same iterates, the specification the parity tests check against.
#pragma once

#include "tmpc/gpu/admm_problem.hpp"
#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {

/// Kinv = (H + sigma I + A'RA)^-1 with the set-up penalty (spectral rule x rho_scale,
/// or options.rho), R x1e3 on equality rows; the thesis variant's H1^-1, H2^-1 with
/// its own penalty (plain spectral rule, or options.rho). Throws std::invalid_argument
/// for options the GPU does not implement (equilibration).
gpu::AdmmProblem make_gpu_problem(const MpcQpData& d, const SolverOptions& options);
/// The same in double (host checks of the kernel code in the precision of the CPU twins).
gpu::BasicAdmmProblem<double> make_gpu_problem_fp64(const MpcQpData& d, const SolverOptions& options);

/// Device settings from solver options for a variant (gpu::kExact or gpu::kThesis).
gpu::AdmmSettings make_gpu_settings(const SolverOptions& options, int variant);

/// CPU options whose iterates the GPU's exact variant reproduces (float aside):
/// adaptive_rho and polish off, no equilibration.
SolverOptions cpu_twin_options(SolverOptions options);

}  // namespace tmpc
