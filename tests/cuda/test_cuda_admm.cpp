// The GPU ADMM on a GPU: parity with the CPU twins on 500 case-study QPs (fused
// kernel, both variants), batched = single, the cuBLAS and graph paths, KKT of the
// float solutions in double, failures as statuses. Every test skips, saying why,
// on a machine without a usable CUDA device (as in CI).
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "../gpu/parity.hpp"
#include "../solvers/case_study_qps.hpp"
#include "admm_device.hpp"
#include "cuda_qp_solver.hpp"
#include "device_info.hpp"
#include "tmpc/solvers/gpu_problem.hpp"

namespace tmpc {
namespace {

using test::case_study_artifact;
using test::case_study_states;
using test::expect_parity;
using test::ParityStats;

/// Empty when a device is usable, else why not.
std::string no_device_reason() {
  cuda::DeviceInfo devs[4];
  char msg[512] = "";
  const int n = cuda::query_devices(devs, 4, msg, sizeof msg);
  if (n < 0) return std::string("no usable CUDA device: ") + msg;
  if (n == 0) return "no CUDA device on this machine";
  std::printf("GPU: %s (sm_%d%d)\n", devs[0].name, devs[0].major, devs[0].minor);
  return "";
}

#define REQUIRE_GPU()                                       \
  do {                                                      \
    const std::string why = no_device_reason();             \
    if (!why.empty()) GTEST_SKIP() << why;                  \
  } while (0)

std::vector<float> to_float(const Eigen::VectorXd& x) {
  std::vector<float> v(static_cast<std::size_t>(x.size()));
  for (Eigen::Index i = 0; i < x.size(); ++i) v[static_cast<std::size_t>(i)] = static_cast<float>(x(i));
  return v;
}
Eigen::VectorXd to_double(const float* p, int n) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = p[i];
  return v;
}

struct CaseStudy {
  MpcQpData d = case_study_artifact().qp();
  SolverOptions o;
  Eigen::VectorXd u_range;
  explicit CaseStudy(bool warm) {
    o = cpu_twin_options(SolverOptions{});
    o.warm_start = warm;
    u_range = d.u_bar.hi - d.u_bar.lo;
  }
};

/// Fused single solves of `variant` against the CPU twin.
/// max_iterations > 0 replaces the iteration cap of both.
ParityStats fused_parity(int variant, const std::vector<Eigen::VectorXd>& xs, bool warm, cuda::DeviceOptions dopt = {},
                         int max_iterations = 0) {
  CaseStudy s(warm);
  if (max_iterations > 0) s.o.max_iterations = max_iterations;
  auto cpu = make_solver(variant == gpu::kExact ? "admm" : "admm-thesis", s.d, s.o);
  cuda::AdmmDevice dev(make_gpu_problem(s.d, s.o), make_gpu_settings(s.o, variant), dopt);
  EXPECT_TRUE(dev.ok()) << dev.error();
  ParityStats st;
  if (!dev.ok()) return st;
  std::printf("fused kernel: %d bytes of shared memory, matrices %s\n", dev.fused_shared_bytes(),
              dev.fused_matrices_staged() ? "staged" : "in global memory");
  Eigen::VectorXd y(s.d.M * s.d.m + s.d.N * s.d.n);
  std::vector<float> yf(static_cast<std::size_t>(y.size()));
  for (const Eigen::VectorXd& x0 : xs) {
    const SolveResult& c = cpu->solve(x0);
    const std::vector<float> xf = to_float(x0);
    EXPECT_TRUE(dev.start(xf.data())) << dev.error();
    int polls = 0;
    while (dev.query() == 0) ++polls;  // the real-time loop's non-blocking completion test
    const Eigen::VectorXd z = to_double(dev.z(), dev.nz());
    const bool exact = variant == gpu::kExact;
    if (exact) {
      EXPECT_TRUE(dev.copy_multipliers(yf.data())) << dev.error();
      y = to_double(yf.data(), static_cast<int>(yf.size()));
    }
    st.add(*cpu, c, x0, s.u_range, dev.outcome().status, dev.outcome().iterations, z, exact ? &y : nullptr,
           exact ? s.o.check_every : 1);
  }
  st.finish(variant == gpu::kExact ? "GPU fused exact" : "GPU fused thesis");
  return st;
}

TEST(CudaAdmm, FusedExactMatchesCpuOnFiveHundredQps) {
  REQUIRE_GPU();
  const ParityStats st = fused_parity(gpu::kExact, case_study_states(500, 3), false);
  expect_parity(st);
  EXPECT_LE(st.worst_prim, 5e-3);  // KKT consistent with epsilon = 1e-3
  EXPECT_LE(st.worst_stat, 5e-3);
}

TEST(CudaAdmm, FusedExactWithMatricesInGlobalMemory) {
  REQUIRE_GPU();
  cuda::DeviceOptions dopt;
  dopt.stage_matrices = false;
  dopt.threads = 128;
  expect_parity(fused_parity(gpu::kExact, case_study_states(100, 11), false, dopt));
}

TEST(CudaAdmm, FusedExactWithTheBlockFormInSharedMemory) {
  REQUIRE_GPU();
  cuda::DeviceOptions dopt;
  dopt.prefer_block_form = true;  // as on a TX2, where the dense A does not fit
  expect_parity(fused_parity(gpu::kExact, case_study_states(100, 19), false, dopt));
  CaseStudy s(false);
  cuda::AdmmDevice dev(make_gpu_problem(s.d, s.o), make_gpu_settings(s.o, gpu::kExact), dopt);
  ASSERT_TRUE(dev.ok()) << dev.error();
  EXPECT_TRUE(dev.fused_block_form());
}

TEST(CudaAdmm, FusedThesisMatchesItsCpuTwin) {
  REQUIRE_GPU();
  // Float needs more iterations of the literal algorithm than double (measured +34 %
  // on the host run of the same code, tests/gpu; +31 % on an H200 with the cap
  // raised): status and u must agree; the iteration count is bounded as measured. The
  // cap is raised for both (4000 -> 8000): at the shipped cap 2 of these 100 QPs ended
  // with other statuses on an H200, the float run needing iterations past the cap.
  const ParityStats st = fused_parity(gpu::kThesis, case_study_states(100, 4), false, {}, 8000);
  expect_parity(st, false);
  EXPECT_LE(st.iters_gpu, 1.5 * st.iters_cpu);
}

TEST(CudaAdmm, FusedWarmStartOnAClosedLoopLikeSequence) {
  REQUIRE_GPU();
  std::vector<Eigen::VectorXd> xs;
  Eigen::VectorXd x = case_study_states(1, 7)[0];
  for (int k = 0; k < 100; ++k) {
    xs.push_back(x);
    x *= 0.97;
  }
  expect_parity(fused_parity(gpu::kExact, xs, true));
}

TEST(CudaAdmm, BatchedEqualsSingleSolves) {
  REQUIRE_GPU();
  CaseStudy s(false);
  const auto xs = case_study_states(500, 12);
  const int B = static_cast<int>(xs.size());
  for (const bool same_launch_shape : {true, false}) {
    cuda::DeviceOptions dopt;
    dopt.max_batch = B;
    if (same_launch_shape) {  // the same block shape: the same float operations
      dopt.batch_threads = dopt.threads;
      dopt.batch_stage_matrices = dopt.stage_matrices;
    }
    cuda::AdmmDevice dev(make_gpu_problem(s.d, s.o), make_gpu_settings(s.o, gpu::kExact), dopt);
    ASSERT_TRUE(dev.ok()) << dev.error();
    std::vector<float> x0s;
    for (const auto& x : xs) {
      const std::vector<float> f = to_float(x);
      x0s.insert(x0s.end(), f.begin(), f.end());
    }
    std::vector<gpu::AdmmOutcome> out(static_cast<std::size_t>(B));
    std::vector<float> z(static_cast<std::size_t>(B) * dev.nz());
    ASSERT_TRUE(dev.solve_batch(x0s.data(), B, out.data(), z.data(), false)) << dev.error();
    int worst_iter = 0;
    double worst_dz = 0.0;
    for (int b = 0; b < B; ++b) {
      ASSERT_TRUE(dev.start(x0s.data() + static_cast<std::size_t>(b) * dev.nx()) && dev.wait()) << dev.error();
      EXPECT_EQ(out[static_cast<std::size_t>(b)].status, dev.outcome().status) << b;
      worst_iter = std::max(worst_iter, std::abs(out[static_cast<std::size_t>(b)].iterations - dev.outcome().iterations));
      for (int i = 0; i < dev.nz(); ++i) {
        worst_dz = std::max(worst_dz, static_cast<double>(std::fabs(z[static_cast<std::size_t>(b) * dev.nz() + i] - dev.z()[i])));
      }
    }
    std::printf("batched vs single (%s launch shape): worst |dz| %.2e, worst iteration difference %d\n",
                same_launch_shape ? "same" : "default", worst_dz, worst_iter);
    if (same_launch_shape) {
      EXPECT_EQ(worst_dz, 0.0);
      EXPECT_EQ(worst_iter, 0);
    } else {
      EXPECT_LE(worst_dz, 1e-4);
      EXPECT_LE(worst_iter, s.o.check_every);
    }
  }
}

TEST(CudaAdmm, BatchedThroughTheSolverRegistry) {
  REQUIRE_GPU();
  register_cuda_solvers();
  CaseStudy s(false);
  const auto xs = case_study_states(64, 13);
  const std::vector<SolveResult> g = solve_batch("admm-cuda", s.d, s.o, xs);
  auto cpu = make_solver("admm", s.d, s.o);
  ParityStats st;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const SolveResult& c = cpu->solve(xs[i]);
    st.add(*cpu, c, xs[i], s.u_range, static_cast<int>(g[i].status), g[i].iterations, g[i].z, nullptr, s.o.check_every);
  }
  st.finish("registry batch");
  expect_parity(st);
}

TEST(CudaAdmm, OffsetFreeFormThroughTheSolverRegistry) {
  REQUIRE_GPU();
  register_cuda_solvers();
  const MpcQpData d = case_study_artifact().qp(true);
  SolverOptions o = cpu_twin_options(SolverOptions{});
  o.warm_start = false;
  auto gpu = make_solver("admm-cuda", d, o);
  auto cpu = make_solver("admm", d, o);
  ASSERT_EQ(gpu->problem().nx(), 24 + 3 + 24);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ParityStats st;
  for (const Eigen::VectorXd& x0 : case_study_states(100, 22)) {
    Eigen::VectorXd t = Eigen::VectorXd::Zero(51);
    t << x0, u(rng), u(rng), u(rng), Eigen::VectorXd::Zero(24);
    const SolveResult& c = cpu->solve(t);
    const SolveResult g = gpu->solve(t);
    st.add(*cpu, c, t, d.u_bar.hi - d.u_bar.lo, static_cast<int>(g.status), g.iterations, g.z, nullptr, o.check_every);
  }
  st.finish("offset-free fused");
  expect_parity(st);
}

// Needs no device: the thesis kernel keeps its sets fixed, so it refuses the
// offset-free form (whose sets move every period) before touching the GPU.
TEST(CudaAdmm, ThesisSolverRefusesTheOffsetFreeForm) {
  register_cuda_solvers();
  EXPECT_THROW(make_solver("admm-cuda-thesis", case_study_artifact().qp(true)), std::invalid_argument);
}

TEST(CudaAdmm, CublasPathMatchesCpu) {
  REQUIRE_GPU();
  CaseStudy s(false);
  auto cpu = make_solver("admm", s.d, s.o);
  cuda::AdmmDevice dev(make_gpu_problem(s.d, s.o), make_gpu_settings(s.o, gpu::kExact), cuda::DeviceOptions{});
  ASSERT_TRUE(dev.ok()) << dev.error();
  ParityStats st;
  for (const Eigen::VectorXd& x0 : case_study_states(100, 14)) {
    const SolveResult& c = cpu->solve(x0);
    const std::vector<float> xf = to_float(x0);
    ASSERT_TRUE(dev.solve_cublas(xf.data())) << dev.error();
    st.add(*cpu, c, x0, s.u_range, dev.outcome().status, dev.outcome().iterations, to_double(dev.z(), dev.nz()), nullptr,
           s.o.check_every);
  }
  st.finish("GPU cuBLAS path");
  expect_parity(st);
}

TEST(CudaAdmm, GraphPathOfFixedIterationsReachesTheSolution) {
  REQUIRE_GPU();
  CaseStudy s(false);
  auto cpu = make_solver("admm", s.d, s.o);
  cuda::DeviceOptions dopt;
  dopt.graph_iterations = 400;  // above the cold iteration counts of these QPs
  cuda::AdmmDevice dev(make_gpu_problem(s.d, s.o), make_gpu_settings(s.o, gpu::kExact), dopt);
  ASSERT_TRUE(dev.ok()) << dev.error();
  double worst_u = 0.0;
  for (const Eigen::VectorXd& x0 : case_study_states(50, 15)) {
    const SolveResult& c = cpu->solve(x0);
    const std::vector<float> xf = to_float(x0);
    ASSERT_TRUE(dev.start_graph(xf.data()) && dev.wait()) << dev.error();
    if (c.iterations <= dopt.graph_iterations) EXPECT_EQ(dev.outcome().status, gpu::kConverged);
    const Eigen::VectorXd z = to_double(dev.z(), dev.nz());
    worst_u = std::max(worst_u, ((z.head(4) - c.z.head(4)).cwiseQuotient(s.u_range)).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst_u, 1e-3);
}

TEST(CudaAdmm, FailuresAreStatuses) {
  REQUIRE_GPU();
  register_cuda_solvers();
  CaseStudy s(false);
  auto solver = make_solver("admm-cuda", s.d, s.o);
  Eigen::VectorXd x = case_study_states(1, 16)[0];
  x(3) = std::nan("");
  EXPECT_EQ(solver->solve(x).status, SolveStatus::InvalidInput);
  EXPECT_EQ(solver->solve(Eigen::VectorXd::Zero(3)).status, SolveStatus::InvalidInput);
  // A spent time budget ends the kernel's loop.
  SolverOptions tight = s.o;
  tight.time_budget_us = 1.0;
  tight.eps_abs = 1e-12;
  tight.eps_rel = 0.0;
  auto slow = make_solver("admm-cuda", s.d, tight);
  EXPECT_EQ(slow->solve(case_study_states(1, 17)[0]).status, SolveStatus::TimeBudget);
  // Non-finite problem data: a numerical failure, not a crash.
  gpu::AdmmProblem p = make_gpu_problem(s.d, s.o);
  p.f0[0] = std::nanf("");
  cuda::AdmmDevice dev(p, make_gpu_settings(s.o, gpu::kExact), cuda::DeviceOptions{});
  ASSERT_TRUE(dev.ok()) << dev.error();
  const std::vector<float> xf = to_float(case_study_states(1, 18)[0]);
  ASSERT_TRUE(dev.start(xf.data()) && dev.wait());
  EXPECT_EQ(dev.outcome().status, gpu::kNumericalFailure);
  // A batch larger than the set-up allows is refused with a reason.
  gpu::AdmmOutcome o;
  EXPECT_FALSE(dev.solve_batch(xf.data(), 2, &o, nullptr, false));
  EXPECT_NE(std::string(dev.error()).find("batch"), std::string::npos);
}

TEST(CudaAdmm, ABlockTooLargeForTheKernelIsRefusedAtSetUpNotAtLaunch) {
  REQUIRE_GPU();
  // 1024 threads are within CUDA's block limit but not the fused kernel's (registers):
  // on an H200 the launch failed with cudaErrorLaunchOutOfResources. Set-up says so.
  CaseStudy s(false);
  cuda::DeviceOptions big;
  big.threads = 1024;
  cuda::AdmmDevice dev(make_gpu_problem(s.d, s.o), make_gpu_settings(s.o, gpu::kExact), big);
  if (dev.ok()) {  // a device whose registers allow it: then it must solve
    const std::vector<float> xf = to_float(case_study_states(1, 19)[0]);
    ASSERT_TRUE(dev.start(xf.data()) && dev.wait()) << dev.error();
    EXPECT_EQ(dev.outcome().status, gpu::kConverged);
  } else {
    EXPECT_NE(std::string(dev.error()).find("threads a block"), std::string::npos) << dev.error();
  }
}

}  // namespace
}  // namespace tmpc
