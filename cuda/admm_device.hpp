// The GPU ADMM solver (DESIGN.md section 5, GPU): one controller's QP resident on the
// device in float, set up once; per solve only the state goes up and the solution
// and status come back. C++14 and no CUDA headers, so the CPU code and JetPack 4's
// nvcc both use it. Nothing here throws or aborts: every CUDA and cuBLAS call is
// checked, and a failure is a false return with the reason in error(), which the
// runtime answers with its fallback.
//
// Paths (cuda/admm_fused.cu, cuda/admm_cublas.cu):
//   fused    the whole ADMM loop of one solve in one kernel launch (a thread block;
//            the matrices staged in shared memory where they fit), the convergence
//            test and the time budget on the device, state and result in pinned
//            mapped (on Jetson: zero-copy) host memory, completion polled by event
//   batched  the same kernel, one block per QP, B QPs in one launch
//   cublas   the thesis-style baseline: one cuBLAS gemv per matrix product of each
//            iteration, small kernels for the rest, the convergence test on the host
//   graph    the cublas path's iterations for a fixed count captured once in a CUDA
//            Graph and replayed per solve (no host round trip per iteration)
#pragma once

#include "tmpc/gpu/admm_problem.hpp"

namespace tmpc {
namespace cuda {

struct DeviceOptions {
  int device = 0;
  int threads = 256;             ///< fused path: threads a block (a multiple of 32)
  int batch_threads = 128;       ///< batched path: threads a block
  int max_batch = 0;             ///< QPs a batched launch may hold (buffers allocated at set-up)
  bool stage_matrices = true;    ///< copy the matrices to shared memory when they fit (fused),
                                 ///< A and P by their repeating blocks if only that fits
  bool batch_stage_matrices = false;  ///< the same for the batched path (occupancy trade-off)
  bool prefer_block_form = false;  ///< stage A and P by their blocks even where dense fits (tests, TX2-like budgets)
  bool cublas_path = true;       ///< set up the thesis-style and graph paths (exact variant)
  int graph_iterations = 0;      ///< > 0: capture the graph path with this iteration count
};

class AdmmDevice {
 public:
  AdmmDevice(const gpu::AdmmProblem& problem, const gpu::AdmmSettings& settings, const DeviceOptions& options);
  ~AdmmDevice();
  AdmmDevice(const AdmmDevice&) = delete;
  AdmmDevice& operator=(const AdmmDevice&) = delete;

  /// False when set-up failed (no device, out of memory, bad problem): error() says why.
  bool ok() const;
  const char* error() const;
  int nz() const;
  int nc() const;
  int nx() const;
  /// Shared memory bytes of a fused launch and whether the matrices are staged there.
  int fused_shared_bytes() const;
  bool fused_matrices_staged() const;
  /// True when the staged A (or P) is held by its repeating blocks (dense did not fit).
  bool fused_block_form() const;

  // --- fused single-solve path (non-blocking) ---
  /// Launch one solve from state x0 (nx floats). False if the launch failed.
  bool start(const float* x0);
  /// 1: finished, 0: still running, -1: failed (error()).
  int query();
  /// Block until the running solve ends; false on failure.
  bool wait();
  /// The last finished solve (fused or graph path): status, iterations, residuals.
  const gpu::AdmmOutcome& outcome() const;
  /// Its solution u_hat (nz floats; u_bar(0) is the first m).
  const float* z() const;
  /// Its multipliers (nc floats, exact variant) copied into y; false on failure.
  bool copy_multipliers(float* y);
  /// Forget every warm start (the next solves are cold).
  bool reset();

  // --- thesis-style cuBLAS path (exact variant, no Nesterov), blocking ---
  bool solve_cublas(const float* x0);
  // --- graph path: start_graph, then query()/wait() as for start() ---
  bool start_graph(const float* x0);

  // --- batched path, blocking: B QPs from x0s (B x nx, row-major) ---
  /// outcomes: B entries; z: B x nz floats or nullptr; warm: start each QP from its
  /// slot's previous solution (closed-loop campaigns), else cold.
  bool solve_batch(const float* x0s, int B, gpu::AdmmOutcome* outcomes, float* z, bool warm);

  struct Impl;  ///< opaque (cuda/admm_device_impl.cuh)

 private:
  Impl* impl_;
};

}  // namespace cuda
}  // namespace tmpc
