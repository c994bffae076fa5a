// GPU ADMM benchmarks (needs a CUDA device; every benchmark says why it skips
// without one). Host-to-host latency per solve (state up, solve, result down) of
// the fused kernel, the CUDA Graph and the thesis-style cuBLAS paths at N in
// {10, 20, 40}, the fused kernel's fixed cost (its loop capped at one iteration) and
// its block sizes (128 to 1024 threads); batched throughput for B in {1, 64, 1024,
// 16384, 65536} against the CPU solver on one core in the same run.
#include <algorithm>
#include <chrono>
#include <string>

#include <benchmark/benchmark.h>

#include "admm_device.hpp"
#include "bench_main.hpp"
#include "case_study.hpp"
#include "device_info.hpp"
#include "tmpc/solvers/gpu_problem.hpp"

namespace {

using bench_case::cold_states;
using bench_case::data_for;
using bench_case::warm_states;
using Clock = std::chrono::steady_clock;

std::string no_device_reason() {
  tmpc::cuda::DeviceInfo devs[4];
  char msg[512] = "";
  const int n = tmpc::cuda::query_devices(devs, 4, msg, sizeof msg);
  if (n < 0) return std::string("no usable CUDA device: ") + msg;
  if (n == 0) return "no CUDA device on this machine";
  return "";
}

std::vector<float> flat_states(const std::vector<Eigen::VectorXd>& xs) {
  std::vector<float> v;
  for (const Eigen::VectorXd& x : xs)
    for (Eigen::Index i = 0; i < x.size(); ++i) v.push_back(static_cast<float>(x(i)));
  return v;
}

enum Path { kFused = 0, kGraph = 1, kCublas = 2, kFusedBlock = 3 };

/// Host-to-host latency of one solve; max_iterations > 0 caps the loop (the fixed cost
/// of a solve: launch, staging, one residual check, completion, transfers).
void latency(benchmark::State& st, int path, int variant, int N, bool warm, int max_iterations = 0, int threads = 0) {
  const std::string why = no_device_reason();
  if (!why.empty()) {
    st.SkipWithError(why.c_str());
    return;
  }
  const tmpc::MpcQpData d = data_for(N);
  tmpc::SolverOptions o = tmpc::cpu_twin_options(tmpc::SolverOptions{});
  o.warm_start = warm;
  const std::vector<Eigen::VectorXd> xs = warm ? warm_states(d, 200) : cold_states(200);
  const std::vector<float> x0s = flat_states(xs);
  const tmpc::gpu::AdmmProblem p = tmpc::make_gpu_problem(d, o);
  tmpc::gpu::AdmmSettings s = tmpc::make_gpu_settings(o, variant);
  if (max_iterations > 0) s.max_iterations = max_iterations;
  tmpc::cuda::DeviceOptions dopt;
  if (threads > 0) dopt.threads = threads;
  dopt.prefer_block_form = path == kFusedBlock;
  if (path == kGraph) {
    // A fixed count every benchmark state converges within: the fused kernel's most.
    tmpc::cuda::AdmmDevice probe(p, s, tmpc::cuda::DeviceOptions{});
    int most = 0;
    for (std::size_t k = 0; k < xs.size() && probe.ok(); ++k) {
      if (probe.start(x0s.data() + k * p.nx) && probe.wait()) most = std::max(most, probe.outcome().iterations);
    }
    dopt.graph_iterations = std::max(most, 1);
  }
  tmpc::cuda::AdmmDevice dev(p, s, dopt);
  if (!dev.ok()) {
    st.SkipWithError(dev.error());
    return;
  }
  std::vector<double> times;
  double iters = 0.0;
  int converged = 0;
  std::size_t k = 0;
  for (auto _ : st) {
    const float* x0 = x0s.data() + (k % xs.size()) * p.nx;
    const auto t0 = Clock::now();
    bool ok = false;
    if (path == kFused || path == kFusedBlock) {
      ok = dev.start(x0);
      while (ok && dev.query() == 0) {
      }
    } else if (path == kGraph) {
      ok = dev.start_graph(x0);
      while (ok && dev.query() == 0) {
      }
    } else {
      ok = dev.solve_cublas(x0);
    }
    times.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    if (!ok) {
      st.SkipWithError(dev.error());
      return;
    }
    iters += dev.outcome().iterations;
    converged += dev.outcome().status == tmpc::gpu::kConverged;
    ++k;
  }
  st.counters["iterations"] = iters / static_cast<double>(times.size());
  st.counters["converged_pct"] = 100.0 * converged / static_cast<double>(times.size());
  st.counters["shared_bytes"] = dev.fused_shared_bytes();
  if (path == kGraph) st.counters["graph_iterations"] = dopt.graph_iterations;
  bench_case::time_counters(st, std::move(times));
}

void batched(benchmark::State& st, int B, bool stage) {
  const std::string why = no_device_reason();
  if (!why.empty()) {
    st.SkipWithError(why.c_str());
    return;
  }
  const tmpc::MpcQpData d = data_for(20);
  const tmpc::SolverOptions o = tmpc::cpu_twin_options(tmpc::SolverOptions{});
  std::vector<Eigen::VectorXd> xs = cold_states(std::min(B, 4096));
  while (static_cast<int>(xs.size()) < B) xs.push_back(xs[xs.size() % 4096]);
  const std::vector<float> x0s = flat_states(xs);
  tmpc::cuda::DeviceOptions dopt;
  dopt.max_batch = B;
  dopt.cublas_path = false;
  dopt.batch_stage_matrices = stage;
  tmpc::cuda::AdmmDevice dev(tmpc::make_gpu_problem(d, o), tmpc::make_gpu_settings(o, tmpc::gpu::kExact), dopt);
  if (!dev.ok()) {
    st.SkipWithError(dev.error());
    return;
  }
  std::vector<tmpc::gpu::AdmmOutcome> out(static_cast<std::size_t>(B));
  std::vector<float> z(static_cast<std::size_t>(B) * dev.nz());
  double seconds = 0.0, iters = 0.0;
  int converged = 0, launches = 0;
  for (auto _ : st) {
    const auto t0 = Clock::now();
    if (!dev.solve_batch(x0s.data(), B, out.data(), z.data(), false)) {
      st.SkipWithError(dev.error());
      return;
    }
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    ++launches;
    for (const auto& r : out) {
      iters += r.iterations;
      converged += r.status == tmpc::gpu::kConverged;
    }
  }
  st.counters["qps_per_s"] = static_cast<double>(B) * launches / seconds;
  st.counters["launch_ms"] = 1e3 * seconds / launches;
  st.counters["iterations"] = iters / (static_cast<double>(B) * launches);
  st.counters["converged_pct"] = 100.0 * converged / (static_cast<double>(B) * launches);
}

/// The CPU solver on one core over the same kind of QPs (this process, this run).
void cpu_one_core(benchmark::State& st, const std::string& solver, bool twin) {
  const tmpc::MpcQpData d = data_for(20);
  tmpc::SolverOptions o = twin ? tmpc::cpu_twin_options(tmpc::SolverOptions{}) : tmpc::SolverOptions{};
  o.warm_start = false;
  auto s = tmpc::make_solver(solver, d, o);
  const std::vector<Eigen::VectorXd> xs = cold_states(1024);
  double seconds = 0.0;
  long solved = 0;
  for (auto _ : st) {
    const auto t0 = Clock::now();
    for (const Eigen::VectorXd& x : xs) benchmark::DoNotOptimize(s->solve(x).z.data());
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    solved += static_cast<long>(xs.size());
  }
  st.counters["qps_per_s"] = static_cast<double>(solved) / seconds;
}

/// One latency benchmark of `solves` timed solves; `run` takes its state.
template <class Run>
void register_latency(const std::string& name, int solves, Run run) {
  benchmark::RegisterBenchmark(name.c_str(), run)->Unit(benchmark::kMicrosecond)->Iterations(solves)->UseRealTime();
}

void register_all() {
  const char* paths[] = {"fused", "graph", "cublas", "fused_block"};
  for (int N : {10, 20, 40}) {
    const std::string at = "/N:" + std::to_string(N);
    for (int path : {kFused, kGraph, kCublas, kFusedBlock}) {
      for (bool warm : {false, true}) {
        if ((path == kGraph || path == kFusedBlock) && warm) continue;  // cold only
        // The host-driven paths take milliseconds a solve (an H200: up to 46 ms at
        // N = 40): fewer solves keep the whole benchmark inside a short device lease.
        const int solves = path == kGraph || path == kCublas ? 300 : 2000;
        register_latency(std::string("latency/exact/") + paths[path] + at + (warm ? "/warm" : "/cold"), solves,
                         [=](benchmark::State& st) { latency(st, path, tmpc::gpu::kExact, N, warm); });
      }
    }
    register_latency("latency/exact/fused" + at + "/one_iteration", 2000,
                     [=](benchmark::State& st) { latency(st, kFused, tmpc::gpu::kExact, N, false, 1); });
    if (N == 20) {  // the block's size against the default 256
      for (int threads : {128, 512, 1024}) {
        for (bool warm : {false, true}) {
          register_latency("latency/exact/fused" + at + (warm ? "/warm" : "/cold") + "/threads:" + std::to_string(threads),
                           2000, [=](benchmark::State& st) { latency(st, kFused, tmpc::gpu::kExact, N, warm, 0, threads); });
        }
      }
    }
    register_latency("latency/thesis/fused" + at + "/warm", 500,
                     [=](benchmark::State& st) { latency(st, kFused, tmpc::gpu::kThesis, N, true); });
  }
  for (int B : {1, 64, 1024, 16384, 65536}) {
    for (bool stage : {false, true}) {
      const std::string name = "batch/exact/B:" + std::to_string(B) + (stage ? "/staged" : "/global");
      benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) { batched(st, B, stage); })
          ->Unit(benchmark::kMillisecond)
          ->MinTime(1.0)
          ->UseRealTime();
    }
  }
  benchmark::RegisterBenchmark("cpu_one_core/admm", [](benchmark::State& st) { cpu_one_core(st, "admm", false); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("cpu_one_core/admm_twin", [](benchmark::State& st) { cpu_one_core(st, "admm", true); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

}  // namespace

int main(int argc, char** argv) { return bench_case::run_registered(argc, argv, register_all); }
