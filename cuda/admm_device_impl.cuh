// Internal state of AdmmDevice shared by its .cu files: device copies of the
// problem, per-slot memory, pinned buffers, streams, events, cuBLAS.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <cublas_v2.h>
#include <cuda_runtime.h>

#include "admm_device.hpp"
#include "tmpc/gpu/admm_kernel.hpp"

namespace tmpc {
namespace cuda {

/// Per-slot arrays of a launch (device or mapped host pointers).
struct SlotArrays {
  float* state;
  int* have_previous;
  gpu::AdmmOutcome* outcome;
  float* z_out;
  float* y_out;  ///< or nullptr
  int state_stride;
};

struct AdmmDevice::Impl {
  gpu::AdmmProblem problem;
  gpu::AdmmSettings settings;
  DeviceOptions options;
  std::string error;
  bool ok = false;
  cudaStream_t stream = nullptr;
  cudaEvent_t done = nullptr;
  std::vector<void*> device_blocks;  // every cudaMalloc, freed at destruction
  gpu::ProblemView<float> view{};   // device pointers, ld = cols, dense A and P
  gpu::ProblemView<float> view_block{};  // the same with A and P in block form (if the problem has it)
  bool block_fused = false, block_batch = false;  // a path launches with view_block
  int state_stride = 0;
  int ws_fused = 0, ws_batch = 0;   // workspace floats a block
  int smem_fused = 0, smem_batch = 0;
  bool stage_fused = false, stage_batch = false;
  // Slots 0..max_batch-1: batched path; slot max_batch: the single-solve paths.
  float* d_state = nullptr;
  int* d_have_previous = nullptr;
  gpu::AdmmOutcome* d_outcomes = nullptr;
  float* d_z = nullptr;
  float* d_y = nullptr;
  float* d_x0s = nullptr;
  // Pinned mapped host memory of the single-solve path.
  float* h_x0 = nullptr;
  float* h_z = nullptr;
  gpu::AdmmOutcome* h_outcome = nullptr;
  float* m_x0 = nullptr;  // their device aliases
  float* m_z = nullptr;
  gpu::AdmmOutcome* m_outcome = nullptr;
  // Pinned staging of the batched path.
  float* h_batch_x0 = nullptr;
  gpu::AdmmOutcome* h_batch_outcomes = nullptr;
  float* h_batch_z = nullptr;
  gpu::AdmmOutcome last{};  // what outcome() returns
  // Unfused (cuBLAS and graph) path.
  cublasHandle_t cublas = nullptr;
  struct Unfused {
    float *x0, *x, *xt, *rhs, *f, *Hx, *Aty, *z, *y, *zt, *lo, *hi, *tm, *xs, *zs, *res;
    int* have_previous;
  } u{};
  float* h_res = nullptr;  // pinned: residual maxima and the result of the graph path
  float* h_graph_z = nullptr;
  cudaGraphExec_t graph = nullptr;
  cudaGraph_t graph_def = nullptr;
  bool unfused_result = false;  // the last solve ran on the unfused buffers (cuBLAS or graph path)
  bool graph_started = false;  // query()/wait() finish a graph launch

  bool check(cudaError_t e, const char* what);
  bool check(cublasStatus_t s, const char* what);
  template <class T>
  bool alloc(T*& p, std::size_t count, const char* what) {
    void* v = nullptr;
    if (!check(cudaMalloc(&v, count * sizeof(T) + 16), what)) return false;
    device_blocks.push_back(v);
    p = static_cast<T*>(v);
    return true;
  }
  bool upload(const std::vector<float>& h, const float*& d, const char* what);
  bool setup();
  bool setup_unfused();
  bool host_alloc_pinned(float*& h, std::size_t count);
  bool launch_fused(const float* x0s, int blocks, const SlotArrays& slots, bool batch);
  void release();
};

/// Launch the fused kernel of `variant` (admm_fused.cu).
cudaError_t launch_fused_kernel(int variant, const gpu::ProblemView<float>& view, const gpu::AdmmSettings& s,
                                const float* x0s, const SlotArrays& slots, int blocks, int threads, int ws_floats,
                                int smem_bytes, bool stage, cudaStream_t stream);
/// Shared-memory floats the staged matrices of `variant` take (0 if not staged).
int staged_matrix_floats(int variant, const gpu::ProblemView<float>& v);
/// The graph path's outcome from the residual maxima it left in h_res (admm_cublas.cu).
void graph_outcome(AdmmDevice::Impl& im);
/// The most threads a block of the fused kernel of `variant` can launch with on the
/// current device (its registers a thread bound it: on an H200, 1024 failed at launch).
cudaError_t fused_kernel_max_threads(int variant, int* most);
/// Allow `bytes` of dynamic shared memory for the kernel of `variant`.
cudaError_t allow_shared_memory(int variant, int bytes);

}  // namespace cuda
}  // namespace tmpc
