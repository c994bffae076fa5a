// AdmmDevice: set-up (device copies, slots, pinned buffers), the fused single-solve
// path and the batched path. Every CUDA call is checked; failures become statuses.
#include <cstring>
#include <utility>

#include "admm_device_impl.cuh"

namespace tmpc {
namespace cuda {

bool AdmmDevice::Impl::check(cudaError_t e, const char* what) {
  if (e == cudaSuccess) return true;
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s: %s (%s)", what, cudaGetErrorString(e), cudaGetErrorName(e));
  error = buf;
  return false;
}

bool AdmmDevice::Impl::check(cublasStatus_t s, const char* what) {
  if (s == CUBLAS_STATUS_SUCCESS) return true;
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s: cuBLAS status %d", what, static_cast<int>(s));
  error = buf;
  return false;
}

bool AdmmDevice::Impl::upload(const std::vector<float>& h, const float*& d, const char* what) {
  float* p = nullptr;
  if (!alloc(p, h.size(), what)) return false;
  if (!check(cudaMemcpy(p, h.data(), h.size() * sizeof(float), cudaMemcpyHostToDevice), what)) return false;
  d = p;
  return true;
}

namespace {
template <class T>
bool host_alloc(AdmmDevice::Impl& im, T*& h, T*& d, std::size_t count, const char* what) {
  void* p = nullptr;
  if (!im.check(cudaHostAlloc(&p, count * sizeof(T) + 16, cudaHostAllocMapped), what)) return false;
  std::memset(p, 0, count * sizeof(T) + 16);
  h = static_cast<T*>(p);
  void* dp = nullptr;
  if (!im.check(cudaHostGetDevicePointer(&dp, p, 0), what)) return false;
  d = static_cast<T*>(dp);
  return true;
}
int pad32(int n) { return ((n + 31) / 32) * 32; }
}  // namespace

bool AdmmDevice::Impl::setup() {
  const gpu::AdmmProblem& p = problem;
  const char* bad = p.check();
  if (bad[0] != '\0') {
    error = std::string("GPU problem: ") + bad;
    return false;
  }
  if (options.threads < 32 || options.threads > 1024 || options.threads % 32 != 0 || options.batch_threads < 32 ||
      options.batch_threads > 1024 || options.batch_threads % 32 != 0) {
    error = "GPU options: threads and batch_threads must be multiples of 32 in [32, 1024]";
    return false;
  }
  if (options.max_batch < 0) {
    error = "GPU options: max_batch must be >= 0";
    return false;
  }
  if (!check(cudaSetDevice(options.device), "cudaSetDevice")) return false;
  int most_threads = 0;
  if (!check(fused_kernel_max_threads(settings.variant, &most_threads), "cudaFuncGetAttributes")) return false;
  if (options.threads > most_threads || options.batch_threads > most_threads) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "GPU options: %d threads a block asked for, the fused kernel launches with at most %d on this device "
                  "(its registers a thread)",
                  options.threads > options.batch_threads ? options.threads : options.batch_threads, most_threads);
    error = buf;
    return false;
  }
  if (!check(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking), "cudaStreamCreate")) return false;
  if (!check(cudaEventCreateWithFlags(&done, cudaEventDisableTiming), "cudaEventCreate")) return false;
  bool uploaded = true;
  std::vector<std::pair<const std::vector<float>*, const float*>> copies;  // each array once
  auto where = [&](const std::vector<float>& h) -> const float* {
    for (const auto& c : copies) {
      if (c.first == &h) return c.second;
    }
    const float* d = nullptr;
    if (uploaded && !upload(h, d, "copy of the QP data to the device")) uploaded = false;
    copies.emplace_back(&h, d);
    return d;
  };
  view = gpu::view_of(p, where);
  view_block = gpu::view_of(p, where, true);
  if (!uploaded) return false;

  const int slots = options.max_batch + 1;
  state_stride = gpu::state_floats(p.nz, p.nc, p.N, p.n);
  if (!alloc(d_state, static_cast<std::size_t>(slots) * state_stride, "cudaMalloc slots") ||
      !alloc(d_have_previous, slots, "cudaMalloc slots") || !alloc(d_outcomes, slots, "cudaMalloc slots") ||
      !alloc(d_z, static_cast<std::size_t>(slots) * p.nz, "cudaMalloc slots") ||
      !alloc(d_y, static_cast<std::size_t>(slots) * p.nc, "cudaMalloc slots") ||
      !alloc(d_x0s, static_cast<std::size_t>(slots) * p.nx, "cudaMalloc slots"))
    return false;
  if (!check(cudaMemset(d_have_previous, 0, slots * sizeof(int)), "cudaMemset")) return false;
  if (!host_alloc(*this, h_x0, m_x0, p.nx, "cudaHostAlloc") || !host_alloc(*this, h_z, m_z, p.nz, "cudaHostAlloc") ||
      !host_alloc(*this, h_outcome, m_outcome, 1, "cudaHostAlloc"))
    return false;
  if (options.max_batch > 0) {
    float* unused = nullptr;
    gpu::AdmmOutcome* unused_o = nullptr;
    if (!host_alloc(*this, h_batch_x0, unused, static_cast<std::size_t>(options.max_batch) * p.nx, "cudaHostAlloc") ||
        !host_alloc(*this, h_batch_outcomes, unused_o, options.max_batch, "cudaHostAlloc") ||
        !host_alloc(*this, h_batch_z, unused, static_cast<std::size_t>(options.max_batch) * p.nz, "cudaHostAlloc"))
      return false;
  }

  // Shared memory: reduction scratch, x0, workspace, and the matrices where they fit.
  int max_smem = 0;
  if (!check(cudaDeviceGetAttribute(&max_smem, cudaDevAttrMaxSharedMemoryPerBlockOptin, options.device),
             "cudaDeviceGetAttribute"))
    return false;
  const int staged = staged_matrix_floats(settings.variant, view);
  const int staged_block = p.Gblk.empty() ? staged : staged_matrix_floats(settings.variant, view_block);
  ws_fused = gpu::workspace_floats(p.nz, p.nc, p.N, p.n, options.threads);
  ws_batch = gpu::workspace_floats(p.nz, p.nc, p.N, p.n, options.batch_threads);
  const int base_fused = 64 + pad32(p.nx) + ws_fused, base_batch = 64 + pad32(p.nx) + ws_batch;
  if (base_fused * 4 > max_smem || base_batch * 4 > max_smem) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "QP too large for the fused kernel: its workspace needs %d bytes of shared memory, the device has %d",
                  base_fused * 4, max_smem);
    error = buf;
    return false;
  }
  // Staged matrices: dense where they fit, else A and P by their repeating blocks
  // (the TX2's 48 KB at N = 20), else read from global memory (dense, cached).
  auto choose = [&](bool wanted, int base, bool& stage, bool& block) {
    stage = block = false;
    if (!wanted) return base;
    if (!options.prefer_block_form && (base + staged) * 4 <= max_smem) {
      stage = true;
      return base + staged;
    }
    if (!p.Gblk.empty() && (base + staged_block) * 4 <= max_smem) {
      stage = block = true;
      return base + staged_block;
    }
    if ((base + staged) * 4 <= max_smem) {  // preferred the blocks, but the problem has none
      stage = true;
      return base + staged;
    }
    return base;
  };
  smem_fused = 4 * choose(options.stage_matrices, base_fused, stage_fused, block_fused);
  smem_batch = 4 * choose(options.batch_stage_matrices, base_batch, stage_batch, block_batch);
  const int most = smem_fused > smem_batch ? smem_fused : smem_batch;
  if (most > 48 * 1024 && !check(allow_shared_memory(settings.variant, most), "cudaFuncSetAttribute")) return false;
  if (options.cublas_path && settings.variant == gpu::kExact && settings.nesterov == 0 && !setup_unfused()) return false;
  return true;
}

bool AdmmDevice::Impl::launch_fused(const float* x0s, int blocks, const SlotArrays& slots, bool batch) {
  const bool block = batch ? block_batch : block_fused;
  return check(launch_fused_kernel(settings.variant, block ? view_block : view, settings, x0s, slots, blocks,
                                   batch ? options.batch_threads : options.threads, batch ? ws_batch : ws_fused,
                                   batch ? smem_batch : smem_fused, batch ? stage_batch : stage_fused, stream),
               "fused ADMM kernel launch");
}

void AdmmDevice::Impl::release() {
  if (stream != nullptr) cudaStreamSynchronize(stream);
  if (graph != nullptr) cudaGraphExecDestroy(graph);
  if (graph_def != nullptr) cudaGraphDestroy(graph_def);
  if (cublas != nullptr) cublasDestroy(cublas);
  for (void* b : device_blocks) cudaFree(b);
  for (void* h : {static_cast<void*>(h_x0), static_cast<void*>(h_z), static_cast<void*>(h_outcome),
                  static_cast<void*>(h_batch_x0), static_cast<void*>(h_batch_outcomes), static_cast<void*>(h_batch_z),
                  static_cast<void*>(h_res), static_cast<void*>(h_graph_z)}) {
    if (h != nullptr) cudaFreeHost(h);
  }
  if (done != nullptr) cudaEventDestroy(done);
  if (stream != nullptr) cudaStreamDestroy(stream);
}

AdmmDevice::AdmmDevice(const gpu::AdmmProblem& problem, const gpu::AdmmSettings& settings, const DeviceOptions& options)
    : impl_(new Impl) {
  impl_->problem = problem;
  impl_->settings = settings;
  impl_->options = options;
  impl_->ok = impl_->setup();
}

AdmmDevice::~AdmmDevice() {
  impl_->release();
  delete impl_;
}

bool AdmmDevice::ok() const { return impl_->ok; }
const char* AdmmDevice::error() const { return impl_->error.c_str(); }
int AdmmDevice::nz() const { return impl_->problem.nz; }
int AdmmDevice::nc() const { return impl_->problem.nc; }
int AdmmDevice::nx() const { return impl_->problem.nx; }
int AdmmDevice::fused_shared_bytes() const { return impl_->smem_fused; }
bool AdmmDevice::fused_matrices_staged() const { return impl_->stage_fused; }
bool AdmmDevice::fused_block_form() const { return impl_->block_fused; }
const gpu::AdmmOutcome& AdmmDevice::outcome() const { return impl_->last; }
const float* AdmmDevice::z() const { return impl_->unfused_result ? impl_->h_graph_z : impl_->h_z; }

bool AdmmDevice::start(const float* x0) {
  Impl& im = *impl_;
  if (!im.ok) return false;
  if (cudaEventQuery(im.done) == cudaErrorNotReady) {  // never two solves in flight
    im.error = "a solve is still in flight";
    return false;
  }
  std::memcpy(im.h_x0, x0, static_cast<std::size_t>(im.problem.nx) * sizeof(float));
  const int s = im.options.max_batch;  // the single-solve slot
  const SlotArrays slot{im.d_state + static_cast<long>(s) * im.state_stride, im.d_have_previous + s, im.m_outcome, im.m_z,
                        im.d_y + static_cast<long>(s) * im.problem.nc, im.state_stride};
  im.unfused_result = false;
  im.graph_started = false;
  im.last.status = gpu::kNumericalFailure;
  if (!im.launch_fused(im.m_x0, 1, slot, false)) return false;
  return im.check(cudaEventRecord(im.done, im.stream), "cudaEventRecord");
}

namespace {
void finish_outcome(AdmmDevice::Impl& im) {
  if (im.graph_started) {
    graph_outcome(im);
  } else {
    im.last = *im.h_outcome;
  }
}
}  // namespace

int AdmmDevice::query() {
  Impl& im = *impl_;
  const cudaError_t e = cudaEventQuery(im.done);
  if (e == cudaErrorNotReady) return 0;
  if (!im.check(e, "cudaEventQuery")) {
    im.last.status = gpu::kNumericalFailure;
    return -1;
  }
  finish_outcome(im);
  return 1;
}

bool AdmmDevice::wait() {
  Impl& im = *impl_;
  if (!im.check(cudaEventSynchronize(im.done), "cudaEventSynchronize")) {
    im.last.status = gpu::kNumericalFailure;
    return false;
  }
  finish_outcome(im);
  return true;
}

bool AdmmDevice::copy_multipliers(float* y) {
  Impl& im = *impl_;
  const float* src = im.unfused_result ? im.u.y : im.d_y + static_cast<long>(im.options.max_batch) * im.problem.nc;
  return im.check(cudaMemcpy(y, src, static_cast<std::size_t>(im.problem.nc) * sizeof(float), cudaMemcpyDeviceToHost),
                  "cudaMemcpy multipliers");
}

bool AdmmDevice::reset() {
  Impl& im = *impl_;
  if (!im.ok) return false;
  if (!im.check(cudaMemsetAsync(im.d_have_previous, 0, (im.options.max_batch + 1) * sizeof(int), im.stream), "cudaMemset"))
    return false;
  if (im.u.have_previous != nullptr &&
      !im.check(cudaMemsetAsync(im.u.have_previous, 0, sizeof(int), im.stream), "cudaMemset"))
    return false;
  return im.check(cudaStreamSynchronize(im.stream), "cudaStreamSynchronize");
}

bool AdmmDevice::solve_batch(const float* x0s, int B, gpu::AdmmOutcome* outcomes, float* z, bool warm) {
  Impl& im = *impl_;
  if (!im.ok) return false;
  if (B < 1 || B > im.options.max_batch) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "batch of %d QPs: this solver was set up for 1 to %d", B, im.options.max_batch);
    im.error = buf;
    return false;
  }
  const gpu::AdmmProblem& p = im.problem;
  std::memcpy(im.h_batch_x0, x0s, static_cast<std::size_t>(B) * p.nx * sizeof(float));
  const SlotArrays slots{im.d_state, im.d_have_previous, im.d_outcomes, im.d_z, nullptr, im.state_stride};
  const bool ok =
      im.check(cudaMemcpyAsync(im.d_x0s, im.h_batch_x0, static_cast<std::size_t>(B) * p.nx * sizeof(float),
                               cudaMemcpyHostToDevice, im.stream),
               "cudaMemcpyAsync batch states") &&
      (warm || im.check(cudaMemsetAsync(im.d_have_previous, 0, B * sizeof(int), im.stream), "cudaMemsetAsync")) &&
      im.launch_fused(im.d_x0s, B, slots, true) &&
      im.check(cudaMemcpyAsync(im.h_batch_outcomes, im.d_outcomes, B * sizeof(gpu::AdmmOutcome), cudaMemcpyDeviceToHost,
                               im.stream),
               "cudaMemcpyAsync batch outcomes") &&
      (z == nullptr || im.check(cudaMemcpyAsync(im.h_batch_z, im.d_z, static_cast<std::size_t>(B) * p.nz * sizeof(float),
                                                cudaMemcpyDeviceToHost, im.stream),
                                "cudaMemcpyAsync batch solutions")) &&
      im.check(cudaStreamSynchronize(im.stream), "batched ADMM");
  if (!ok) return false;
  std::memcpy(outcomes, im.h_batch_outcomes, B * sizeof(gpu::AdmmOutcome));
  if (z != nullptr) std::memcpy(z, im.h_batch_z, static_cast<std::size_t>(B) * p.nz * sizeof(float));
  return true;
}

}  // namespace cuda
}  // namespace tmpc
