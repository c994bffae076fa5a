// The GPU ADMM behind the QpSolver interface, so the runtime, `tmpc solve`,
// `simulate`, `controller` and `hil` choose it by name when CUDA is built:
//   admm-cuda         exact variant (E3; fixed penalty, no polish), fused kernel
//   admm-cuda-thesis  Algorithm 4.3 (E2 fixed), fused kernel
// A CUDA failure is a NumericalFailure status (the runtime falls back), never an
// exception after set-up; set-up without a usable GPU throws std::runtime_error
// with CUDA's reason.
#pragma once

namespace tmpc {

/// Register both names with make_solver (and their batched paths with solve_batch).
void register_cuda_solvers();

}  // namespace tmpc
