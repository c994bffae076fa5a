// The thesis-style baseline (one cuBLAS gemv per matrix product of each iteration,
// small kernels for the vector steps, the convergence test on the host) and the CUDA
// Graph of its iterations for a fixed count. Exact variant without Nesterov, the
// same iterates as the fused kernel (float summation order aside).
#include <cmath>
#include <cstring>

#include "admm_device_impl.cuh"

namespace tmpc {
namespace cuda {

namespace {

constexpr int kThreads = 256;
int blocks_for(int n) { return (n + kThreads - 1) / kThreads; }

__global__ void k_bounds(float* lo, float* hi, const float* lo0, const float* hi0, const float* ex, int m) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < m) {
    lo[i] = lo0[i] - ex[i];
    hi[i] = hi0[i] - ex[i];
  }
}

__global__ void k_add(float* f, const float* f0, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) f[i] += f0[i];
}

/// x, z from the previous solution shifted one step (or cold), y = 0.
__global__ void k_start(float* x, float* z, float* y, const float* xs, const float* zs, const float* lo, const float* hi,
                        const int* have_previous, int warm_allowed, int nz, int nc, int m, int M, int ns, int N) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  const bool warm = warm_allowed != 0 && *have_previous != 0;
  if (i < nz) x[i] = warm ? gpu::detail::shifted(xs, i, 0, m, M) : 0.0f;
  if (i < nc) {
    float v = 0.0f;
    if (warm) v = i < nz ? gpu::detail::shifted(zs, i, 0, m, M) : gpu::detail::shifted(zs, i, nz, ns, N);
    z[i] = gpu::detail::clampf(v, lo[i], hi[i]);
    y[i] = 0.0f;
  }
}

__global__ void k_tm(float* tm, const float* rho, const float* z, const float* y, int m) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < m) tm[i] = rho[i] * z[i] - y[i];
}

__global__ void k_rhs(float* rhs, const float* x, const float* f, float sigma, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) rhs[i] += sigma * x[i] - f[i];
}

/// Dual steps (4.21), (4.23) around the projection, and x = x~.
__global__ void k_dual(const float* zt, float* z, float* y, const float* lo, const float* hi, const float* rho, float r,
                       float s, int m, float* x, const float* xt, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < m) {
    const float a = zt[i], rh = rho[i];
    const float yhalf = y[i] + r * rh * (a - z[i]);
    const float zz = gpu::detail::clampf(a + yhalf / rh, lo[i], hi[i]);
    z[i] = zz;
    y[i] = yhalf + s * rh * (a - zz);
  }
  if (i < n) x[i] = xt[i];
}

/// One block: res = [||zt - z||, ||zt||, ||z||, ||Hx + f + A'y||, ||Hx||, ||A'y||, ||f||] (inf-norms).
__global__ void k_residuals(const float* zt, const float* z, const float* Hx, const float* f, const float* Aty, int m,
                            int n, float* res) {
  __shared__ float sh[7][kThreads];
  float v[7] = {0, 0, 0, 0, 0, 0, 0};
  for (int i = threadIdx.x; i < m; i += blockDim.x) {
    v[0] = gpu::detail::nan_max(v[0], fabsf(zt[i] - z[i]));
    v[1] = gpu::detail::nan_max(v[1], fabsf(zt[i]));
    v[2] = gpu::detail::nan_max(v[2], fabsf(z[i]));
  }
  for (int j = threadIdx.x; j < n; j += blockDim.x) {
    v[3] = gpu::detail::nan_max(v[3], fabsf(Hx[j] + f[j] + Aty[j]));
    v[4] = gpu::detail::nan_max(v[4], fabsf(Hx[j]));
    v[5] = gpu::detail::nan_max(v[5], fabsf(Aty[j]));
    v[6] = gpu::detail::nan_max(v[6], fabsf(f[j]));
  }
  for (int q = 0; q < 7; ++q) sh[q][threadIdx.x] = v[q];
  __syncthreads();
  for (int w = blockDim.x / 2; w > 0; w >>= 1) {
    if (static_cast<int>(threadIdx.x) < w) {
      for (int q = 0; q < 7; ++q) sh[q][threadIdx.x] = gpu::detail::nan_max(sh[q][threadIdx.x], sh[q][threadIdx.x + w]);
    }
    __syncthreads();
  }
  if (threadIdx.x < 7) res[threadIdx.x] = sh[threadIdx.x][0];
}

/// Keep (x, z) for the next warm start when the residuals are finite.
__global__ void k_save(float* xs, float* zs, const float* x, const float* z, int* have_previous, const float* res, int n,
                       int m) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) xs[i] = x[i];
  if (i < m) zs[i] = z[i];
  if (i == 0) *have_previous = gpu::detail::finite(res[0]) && gpu::detail::finite(res[3]) ? 1 : 0;
}

/// Row-major products with cuBLAS (column-major): a row-major A (r x c) is A' stored
/// column-major with leading dimension c.
bool gemv(AdmmDevice::Impl& im, const gpu::MatView<float>& A, const float* x, float* y) {  // y = A x
  const float one = 1.0f, zero = 0.0f;
  return im.check(cublasSgemv(im.cublas, CUBLAS_OP_T, A.cols, A.rows, &one, A.p, A.ld, x, 1, &zero, y, 1), "cublasSgemv");
}
bool gemv_t(AdmmDevice::Impl& im, const gpu::MatView<float>& A, const float* v, float* y) {  // y = A' v
  const float one = 1.0f, zero = 0.0f;
  return im.check(cublasSgemv(im.cublas, CUBLAS_OP_N, A.cols, A.rows, &one, A.p, A.ld, v, 1, &zero, y, 1), "cublasSgemv");
}

/// The instance (f, lo, hi) from the state in u.x0 and the start point.
bool enqueue_start(AdmmDevice::Impl& im) {
  const gpu::AdmmProblem& p = im.problem;
  AdmmDevice::Impl::Unfused& u = im.u;
  if (!gemv(im, im.view.F, u.x0, u.f) || !gemv(im, im.view.E, u.x0, u.tm)) return false;
  k_add<<<blocks_for(p.nz), kThreads, 0, im.stream>>>(u.f, im.view.f0, p.nz);
  k_bounds<<<blocks_for(p.nc), kThreads, 0, im.stream>>>(u.lo, u.hi, im.view.lo0, im.view.hi0, u.tm, p.nc);
  k_start<<<blocks_for(p.nc), kThreads, 0, im.stream>>>(u.x, u.z, u.y, u.xs, u.zs, u.lo, u.hi, u.have_previous,
                                                          im.settings.warm_start, p.nz, p.nc, p.m, p.M, p.n, p.N);
  return im.check(cudaGetLastError(), "start kernels");
}

/// One ADMM iteration: three gemv and three small kernels.
bool enqueue_iteration(AdmmDevice::Impl& im) {
  const gpu::AdmmProblem& p = im.problem;
  const gpu::AdmmSettings& s = im.settings;
  AdmmDevice::Impl::Unfused& u = im.u;
  k_tm<<<blocks_for(p.nc), kThreads, 0, im.stream>>>(u.tm, im.view.rho_vec, u.z, u.y, p.nc);
  if (!gemv_t(im, im.view.A, u.tm, u.rhs)) return false;
  k_rhs<<<blocks_for(p.nz), kThreads, 0, im.stream>>>(u.rhs, u.x, u.f, s.sigma, p.nz);
  if (!gemv(im, im.view.Kinv, u.rhs, u.xt) || !gemv(im, im.view.A, u.xt, u.zt)) return false;
  k_dual<<<blocks_for(p.nc), kThreads, 0, im.stream>>>(u.zt, u.z, u.y, u.lo, u.hi, im.view.rho_vec, s.r, s.s, p.nc, u.x,
                                                         u.xt, p.nz);
  return im.check(cudaGetLastError(), "iteration kernels");
}

bool enqueue_residuals(AdmmDevice::Impl& im) {
  const gpu::AdmmProblem& p = im.problem;
  AdmmDevice::Impl::Unfused& u = im.u;
  if (!gemv(im, im.view.H, u.x, u.Hx) || !gemv_t(im, im.view.A, u.y, u.Aty)) return false;
  k_residuals<<<1, kThreads, 0, im.stream>>>(u.zt, u.z, u.Hx, u.f, u.Aty, p.nc, p.nz, u.res);
  return im.check(cudaGetLastError(), "residual kernel") &&
         im.check(cudaMemcpyAsync(im.h_res, u.res, 7 * sizeof(float), cudaMemcpyDeviceToHost, im.stream),
                  "cudaMemcpyAsync residuals");
}

bool enqueue_finish(AdmmDevice::Impl& im) {
  const gpu::AdmmProblem& p = im.problem;
  AdmmDevice::Impl::Unfused& u = im.u;
  k_save<<<blocks_for(p.nc), kThreads, 0, im.stream>>>(u.xs, u.zs, u.x, u.z, u.have_previous, u.res, p.nz, p.nc);
  return im.check(cudaGetLastError(), "save kernel") &&
         im.check(cudaMemcpyAsync(im.h_graph_z, u.x, p.nz * sizeof(float), cudaMemcpyDeviceToHost, im.stream),
                  "cudaMemcpyAsync solution");
}

/// The OSQP-style test of the CPU solver on the residual maxima: 1 converged,
/// 0 not yet, -1 not finite.
int converged(const float* r, const gpu::AdmmSettings& s) {
  if (!std::isfinite(r[0]) || !std::isfinite(r[3])) return -1;
  const float eps_p = s.eps_abs + s.eps_rel * std::fmax(r[1], r[2]);
  const float eps_d = s.eps_abs + s.eps_rel * std::fmax(std::fmax(r[4], r[5]), r[6]);
  return r[0] <= eps_p && r[3] <= eps_d ? 1 : 0;
}

long long host_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

}  // namespace

bool AdmmDevice::Impl::setup_unfused() {
  const gpu::AdmmProblem& p = problem;
  if (!check(cublasCreate(&cublas), "cublasCreate") || !check(cublasSetStream(cublas, stream), "cublasSetStream") ||
      !check(cublasSetPointerMode(cublas, CUBLAS_POINTER_MODE_HOST), "cublasSetPointerMode"))
    return false;
  const std::size_t n = static_cast<std::size_t>(p.nz), m = static_cast<std::size_t>(p.nc);
  if (!alloc(u.x0, static_cast<std::size_t>(p.nx), "cudaMalloc") || !alloc(u.x, n, "cudaMalloc") ||
      !alloc(u.xt, n, "cudaMalloc") || !alloc(u.rhs, n, "cudaMalloc") || !alloc(u.f, n, "cudaMalloc") ||
      !alloc(u.Hx, n, "cudaMalloc") || !alloc(u.Aty, n, "cudaMalloc") || !alloc(u.xs, n, "cudaMalloc") ||
      !alloc(u.z, m, "cudaMalloc") || !alloc(u.y, m, "cudaMalloc") || !alloc(u.zt, m, "cudaMalloc") ||
      !alloc(u.lo, m, "cudaMalloc") || !alloc(u.hi, m, "cudaMalloc") || !alloc(u.tm, m, "cudaMalloc") ||
      !alloc(u.zs, m, "cudaMalloc") || !alloc(u.res, 8, "cudaMalloc") || !alloc(u.have_previous, 1, "cudaMalloc"))
    return false;
  if (!check(cudaMemset(u.have_previous, 0, sizeof(int)), "cudaMemset")) return false;
  if (!host_alloc_pinned(h_res, 8) || !host_alloc_pinned(h_graph_z, n)) return false;
#if CUDART_VERSION >= 11040
  // cuBLAS must not allocate inside a stream capture: give it its workspace now.
  float* workspace = nullptr;
  const std::size_t workspace_bytes = 4u << 20;
  if (!alloc(workspace, workspace_bytes / sizeof(float), "cudaMalloc cuBLAS workspace") ||
      !check(cublasSetWorkspace(cublas, workspace, workspace_bytes), "cublasSetWorkspace"))
    return false;
#endif
  if (options.graph_iterations > 0) {
    // One eager pass first (library initialization happens outside the capture).
    if (!check(cudaMemsetAsync(u.x0, 0, p.nx * sizeof(float), stream), "cudaMemsetAsync") || !enqueue_start(*this) ||
        !enqueue_iteration(*this) || !enqueue_residuals(*this) || !check(cudaStreamSynchronize(stream), "warm-up"))
      return false;
    // Capture: upload, instance and start, a fixed number of iterations, the
    // residuals, the warm-start memory and the download, replayed per solve.
    if (!check(cudaStreamBeginCapture(stream, cudaStreamCaptureModeThreadLocal), "cudaStreamBeginCapture")) return false;
    bool ok = check(cudaMemcpyAsync(u.x0, h_x0, p.nx * sizeof(float), cudaMemcpyHostToDevice, stream), "cudaMemcpyAsync") &&
              enqueue_start(*this);
    for (int k = 0; ok && k < options.graph_iterations; ++k) ok = enqueue_iteration(*this);
    ok = ok && enqueue_residuals(*this) && enqueue_finish(*this);
    const bool ended = check(cudaStreamEndCapture(stream, &graph_def), "cudaStreamEndCapture");
    if (!ok || !ended) return false;
#if CUDART_VERSION >= 12000
    if (!check(cudaGraphInstantiate(&graph, graph_def, 0), "cudaGraphInstantiate")) return false;
#else
    if (!check(cudaGraphInstantiate(&graph, graph_def, nullptr, nullptr, 0), "cudaGraphInstantiate")) return false;
#endif
  }
  return true;
}

bool AdmmDevice::Impl::host_alloc_pinned(float*& h, std::size_t count) {
  void* p = nullptr;
  if (!check(cudaHostAlloc(&p, count * sizeof(float) + 16, cudaHostAllocDefault), "cudaHostAlloc")) return false;
  std::memset(p, 0, count * sizeof(float) + 16);
  h = static_cast<float*>(p);
  return true;
}

void graph_outcome(AdmmDevice::Impl& im) {
  const int c = converged(im.h_res, im.settings);
  im.last.status = c > 0 ? gpu::kConverged : (c < 0 ? gpu::kNumericalFailure : gpu::kMaxIterations);
  im.last.iterations = im.options.graph_iterations;
  im.last.restarts = 0;
  im.last.primal_residual = im.h_res[0];
  im.last.dual_residual = im.h_res[3];
}

bool AdmmDevice::solve_cublas(const float* x0) {
  Impl& im = *impl_;
  if (!im.ok || im.cublas == nullptr) {
    if (im.ok) im.error = "the cuBLAS path needs the exact variant without Nesterov and DeviceOptions::cublas_path";
    return false;
  }
  const gpu::AdmmProblem& p = im.problem;
  const gpu::AdmmSettings& s = im.settings;
  const long long t0 = host_ns();
  im.unfused_result = true;  // z() and copy_multipliers() read this path's buffers
  im.graph_started = false;
  im.last.status = gpu::kNumericalFailure;
  std::memcpy(im.h_x0, x0, p.nx * sizeof(float));
  if (!im.check(cudaMemcpyAsync(im.u.x0, im.h_x0, p.nx * sizeof(float), cudaMemcpyHostToDevice, im.stream),
                "cudaMemcpyAsync state") ||
      !enqueue_start(im))
    return false;
  int status = gpu::kMaxIterations, k = 1;
  for (; k <= s.max_iterations; ++k) {
    if (!enqueue_iteration(im)) return false;
    if (k % s.check_every != 0 && k < s.max_iterations) continue;
    // The convergence test on the host: residuals down, wait, decide.
    if (!enqueue_residuals(im) || !im.check(cudaStreamSynchronize(im.stream), "cudaStreamSynchronize")) return false;
    const int c = converged(im.h_res, s);
    if (c != 0) {
      status = c > 0 ? gpu::kConverged : gpu::kNumericalFailure;
      break;
    }
    if (s.time_budget_ns > 0 && host_ns() - t0 > s.time_budget_ns) {
      status = gpu::kTimeBudget;
      break;
    }
  }
  if (!enqueue_residuals(im) || !enqueue_finish(im) || !im.check(cudaStreamSynchronize(im.stream), "cudaStreamSynchronize"))
    return false;
  im.last.status = status;
  im.last.iterations = k < s.max_iterations ? k : s.max_iterations;
  im.last.restarts = 0;
  im.last.primal_residual = im.h_res[0];
  im.last.dual_residual = im.h_res[3];
  return true;
}

bool AdmmDevice::start_graph(const float* x0) {
  Impl& im = *impl_;
  if (!im.ok || im.graph == nullptr) {
    if (im.ok) im.error = "no graph path: set DeviceOptions::graph_iterations (exact variant without Nesterov)";
    return false;
  }
  if (cudaEventQuery(im.done) == cudaErrorNotReady) {  // never two solves in flight
    im.error = "a solve is still in flight";
    return false;
  }
  std::memcpy(im.h_x0, x0, im.problem.nx * sizeof(float));
  im.unfused_result = true;
  im.graph_started = true;
  im.last.status = gpu::kNumericalFailure;
  return im.check(cudaGraphLaunch(im.graph, im.stream), "cudaGraphLaunch") &&
         im.check(cudaEventRecord(im.done, im.stream), "cudaEventRecord");
}

}  // namespace cuda
}  // namespace tmpc
