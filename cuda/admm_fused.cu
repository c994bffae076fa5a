// The fused ADMM kernel: one thread block runs one whole solve (both variants,
// Nesterov, restart, residual checks, time budget) from tmpc/gpu/admm_kernel.hpp,
// the code the host tests check with teams of host threads.
#include "admm_device_impl.cuh"

namespace tmpc {
namespace cuda {

namespace {

/// A thread block as a team (tmpc/gpu/admm_kernel.hpp): barrier, all-reductions by
/// warp shuffles, the GPU's global nanosecond timer. blockDim.x is a multiple of 32.
struct DeviceTeam {
  int rank, size;
  float* red;  // 33 floats of shared memory
  __device__ void sync() { __syncthreads(); }
  __device__ float reduce(float v, bool is_max) {
    for (int o = 16; o > 0; o >>= 1) {
      const float w = __shfl_down_sync(0xffffffffu, v, o);
      v = is_max ? gpu::detail::nan_max(v, w) : v + w;
    }
    const int warp = rank >> 5, lane = rank & 31, warps = (size + 31) >> 5;
    __syncthreads();  // the previous reduction's readers are done with red
    if (lane == 0) red[warp] = v;
    __syncthreads();
    if (warp == 0) {
      v = lane < warps ? red[lane] : (is_max ? -3.0e38f : 0.0f);
      for (int o = 16; o > 0; o >>= 1) {
        const float w = __shfl_down_sync(0xffffffffu, v, o);
        v = is_max ? gpu::detail::nan_max(v, w) : v + w;
      }
      if (lane == 0) red[32] = v;
    }
    __syncthreads();
    return red[32];
  }
  __device__ float sum(float v) { return reduce(v, false); }
  __device__ float max(float v) { return reduce(v, true); }
  __device__ long long now_ns() const {
    unsigned long long t;
    asm volatile("mov.u64 %0, %%globaltimer;" : "=l"(t));
    return static_cast<long long>(t);
  }
};

/// Copy a matrix into shared memory with an odd leading dimension (no bank conflicts
/// for a thread a row nor a thread a column) and return its view there.
__device__ gpu::MatView<float> stage(const gpu::MatView<float>& src, float*& dst) {
  const int ld = src.cols | 1;
  for (int k = threadIdx.x; k < src.rows * src.cols; k += blockDim.x) {
    const int i = k / src.cols, j = k % src.cols;
    dst[i * ld + j] = src.p[static_cast<long>(i) * src.ld + j];
  }
  gpu::MatView<float> v{dst, src.rows, src.cols, ld};
  dst += src.rows * ld;
  return v;
}

/// The block form (G_l, S_l) of A or P copied to shared memory.
__device__ gpu::MatView<float> stage_blocks(const gpu::MatView<float>& src, float*& dst) {
  const int count = src.bN * src.bn * src.bm;
  for (int k = threadIdx.x; k < count; k += blockDim.x) {
    dst[k] = src.G[k];
    dst[count + k] = src.S[k];
  }
  gpu::MatView<float> v = src;
  v.G = dst;
  v.S = dst + count;
  dst += 2 * count;
  return v;
}

__host__ __device__ int staged_floats(const gpu::MatView<float>& m) {
  return m.G != nullptr ? 2 * m.bN * m.bn * m.bm : m.rows * (m.cols | 1);
}

template <int kVariant>
__global__ void admm_fused_kernel(gpu::ProblemView<float> v, gpu::AdmmSettings s, const float* x0s, SlotArrays slots,
                                  int ws_floats, int stage_matrices) {
  extern __shared__ float smem[];
  const int b = blockIdx.x;
  float* red = smem;             // 64 floats
  float* x0 = smem + 64;         // nx, padded to 32
  float* ws = x0 + ((v.nx + 31) / 32) * 32;
  float* mats = ws + ws_floats;
  for (int i = threadIdx.x; i < v.nx; i += blockDim.x) x0[i] = x0s[static_cast<long>(b) * v.nx + i];
  gpu::ProblemView<float> P = v;
  if (stage_matrices) {
    if (kVariant == gpu::kExact) {
      P.A = v.A.G != nullptr ? stage_blocks(v.A, mats) : stage(v.A, mats);
      P.Kinv = stage(v.Kinv, mats);
      P.H = stage(v.H, mats);
    } else {
      P.P = v.P.G != nullptr ? stage_blocks(v.P, mats) : stage(v.P, mats);
      P.H1inv = stage(v.H1inv, mats);
      P.H2last = stage(v.H2last, mats);
    }
  }
  __syncthreads();
  DeviceTeam t{static_cast<int>(threadIdx.x), static_cast<int>(blockDim.x), red};
  gpu::SlotView<float> slot{slots.state + static_cast<long>(b) * slots.state_stride, slots.have_previous + b,
                            slots.outcome + b, slots.z_out + static_cast<long>(b) * v.nz,
                            slots.y_out != nullptr ? slots.y_out + static_cast<long>(b) * v.nc : nullptr};
  if (kVariant == gpu::kExact) {
    gpu::admm_exact(t, P, s, x0, ws, slot);
  } else {
    gpu::admm_thesis(t, P, s, x0, ws, slot);
  }
}

}  // namespace

int staged_matrix_floats(int variant, const gpu::ProblemView<float>& v) {
  if (variant == gpu::kExact) return staged_floats(v.A) + staged_floats(v.Kinv) + staged_floats(v.H);
  return staged_floats(v.P) + staged_floats(v.H1inv) + staged_floats(v.H2last);
}

cudaError_t allow_shared_memory(int variant, int bytes) {
  if (variant == gpu::kExact) {
    return cudaFuncSetAttribute(admm_fused_kernel<gpu::kExact>, cudaFuncAttributeMaxDynamicSharedMemorySize, bytes);
  }
  return cudaFuncSetAttribute(admm_fused_kernel<gpu::kThesis>, cudaFuncAttributeMaxDynamicSharedMemorySize, bytes);
}

cudaError_t fused_kernel_max_threads(int variant, int* most) {
  cudaFuncAttributes a{};
  const cudaError_t e = variant == gpu::kExact ? cudaFuncGetAttributes(&a, admm_fused_kernel<gpu::kExact>)
                                               : cudaFuncGetAttributes(&a, admm_fused_kernel<gpu::kThesis>);
  *most = a.maxThreadsPerBlock;
  return e;
}

cudaError_t launch_fused_kernel(int variant, const gpu::ProblemView<float>& view, const gpu::AdmmSettings& s,
                                const float* x0s, const SlotArrays& slots, int blocks, int threads, int ws_floats,
                                int smem_bytes, bool stage, cudaStream_t stream) {
  if (variant == gpu::kExact) {
    admm_fused_kernel<gpu::kExact><<<blocks, threads, smem_bytes, stream>>>(view, s, x0s, slots, ws_floats, stage ? 1 : 0);
  } else {
    admm_fused_kernel<gpu::kThesis><<<blocks, threads, smem_bytes, stream>>>(view, s, x0s, slots, ws_floats, stage ? 1 : 0);
  }
  return cudaGetLastError();
}

}  // namespace cuda
}  // namespace tmpc
