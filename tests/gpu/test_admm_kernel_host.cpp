// The GPU's ADMM kernel code (tmpc/gpu/admm_kernel.hpp, float) run by teams of host
// threads against its double-precision CPU twins ("admm" with fixed rho and no
// polish; "admm-thesis"), and its solutions against the KKT conditions computed
// here in double. These run everywhere; the same checks on a GPU are in
// tests/cuda/test_cuda_admm.cpp.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "../solvers/case_study_qps.hpp"
#include "host_team.hpp"
#include "parity.hpp"
#include "tmpc/gpu/admm_kernel.hpp"
#include "tmpc/solvers/gpu_problem.hpp"
#include "tmpc/solvers/kkt.hpp"

namespace tmpc {
namespace {

using test::case_study_artifact;
using test::case_study_states;

/// One slot's memory and a team solve of the kernel code in precision R.
template <class R>
class HostKernelSolver {
 public:
  HostKernelSolver(const gpu::BasicAdmmProblem<R>& p, const gpu::AdmmSettings& s, int team, bool block_form = false)
      : p_(p),
        s_(s),
        team_(team),
        view_(gpu::view_of(p_, [](const std::vector<R>& v) { return v.data(); }, block_form)) {
    state_.assign(static_cast<std::size_t>(gpu::state_floats(p.nz, p.nc, p.N, p.n)), R(0));
    ws_.assign(static_cast<std::size_t>(gpu::workspace_floats(p.nz, p.nc, p.N, p.n, team)), R(0));
    z_.assign(static_cast<std::size_t>(p.nz), R(0));
    y_.assign(static_cast<std::size_t>(p.nc), R(0));
  }
  void solve(const Eigen::VectorXd& x0) {
    std::vector<R> x(static_cast<std::size_t>(x0.size()));
    for (Eigen::Index i = 0; i < x0.size(); ++i) x[static_cast<std::size_t>(i)] = static_cast<R>(x0(i));
    const gpu::SlotView<R> slot{state_.data(), &have_previous_, &outcome_, z_.data(), y_.data()};
    test::run_team(team_, [&](test::HostTeam& t) {
      if (s_.variant == gpu::kExact) {
        gpu::admm_exact(t, view_, s_, x.data(), ws_.data(), slot);
      } else {
        gpu::admm_thesis(t, view_, s_, x.data(), ws_.data(), slot);
      }
    });
  }
  void reset() { have_previous_ = 0; }
  const gpu::AdmmOutcome& outcome() const { return outcome_; }
  Eigen::VectorXd z() const { return Eigen::Map<const Eigen::Matrix<R, -1, 1>>(z_.data(), p_.nz).template cast<double>(); }
  Eigen::VectorXd y() const { return Eigen::Map<const Eigen::Matrix<R, -1, 1>>(y_.data(), p_.nc).template cast<double>(); }

 private:
  gpu::BasicAdmmProblem<R> p_;
  gpu::AdmmSettings s_;
  int team_;
  gpu::ProblemView<R> view_;
  std::vector<R> state_, ws_, z_, y_;
  int have_previous_ = 0;
  gpu::AdmmOutcome outcome_;
};

using test::ParityStats;

gpu::BasicAdmmProblem<float> problem_of(const MpcQpData& d, const SolverOptions& o, float) { return make_gpu_problem(d, o); }
gpu::BasicAdmmProblem<double> problem_of(const MpcQpData& d, const SolverOptions& o, double) {
  return make_gpu_problem_fp64(d, o);
}

/// Kernel code in precision R with `team` threads against the CPU twin on `states`.
template <class R>
ParityStats parity(int variant, int team, const std::vector<Eigen::VectorXd>& states, bool warm, bool block_form = false,
                   int max_iterations = 0, int* infeasible = nullptr, bool offset_free = false) {
  const ControllerArtifact& a = case_study_artifact();
  const MpcQpData d = a.qp(offset_free);
  SolverOptions o = cpu_twin_options(SolverOptions{});
  o.warm_start = warm;
  if (max_iterations > 0) o.max_iterations = max_iterations;
  auto cpu = make_solver(variant == gpu::kExact ? "admm" : "admm-thesis", d, o);
  HostKernelSolver<R> k(problem_of(d, o, R(0)), make_gpu_settings(o, variant), team, block_form);
  const Eigen::VectorXd u_range = d.u_bar.hi - d.u_bar.lo;
  ParityStats st;
  for (const Eigen::VectorXd& x0 : states) {
    const SolveResult& c = cpu->solve(x0);
    k.solve(x0);
    const Eigen::VectorXd y = k.y();
    st.add(*cpu, c, x0, u_range, k.outcome().status, k.outcome().iterations, k.z(),
           variant == gpu::kExact ? &y : nullptr, variant == gpu::kExact ? o.check_every : 1);
    if (infeasible != nullptr) *infeasible += k.outcome().status == gpu::kInfeasible;
  }
  char what[128];
  std::snprintf(what, sizeof what, "%s variant %d team %d warm %d%s%s", sizeof(R) == 4 ? "float" : "double", variant,
                team, warm ? 1 : 0, block_form ? " block form" : "", offset_free ? " offset-free" : "");
  st.finish(what);
  return st;
}

using test::expect_parity;

TEST(GpuKernelOnHost, ExactVariantMatchesCpuTwinOnFiveHundredQps) {
  const ParityStats st = parity<float>(gpu::kExact, 1, case_study_states(500, 3), false);
  expect_parity(st);
  test::expect_exact_twin(st, 10);  // measured: 2 of 500, one check apart
  // KKT of the float solutions, in double: consistent with epsilon = 1e-3.
  EXPECT_LE(st.worst_prim, 5e-3);
  EXPECT_LE(st.worst_stat, 5e-3);
}

TEST(GpuKernelOnHost, OffsetFreeFormMatchesTheCpuTwin) {
  // Parameters (x0, d, c): the kernel forms the shifted bounds through E like any x0.
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> thetas;
  for (const Eigen::VectorXd& x0 : case_study_states(100, 12)) {
    Eigen::VectorXd t(24 + 3 + 24);
    t << x0, u(rng), u(rng), u(rng), Eigen::VectorXd::Zero(24);
    for (int i = 0; i < 24; ++i) t(27 + i) = 1e-5 * u(rng);
    thetas.push_back(t);
  }
  const ParityStats st = parity<float>(gpu::kExact, 3, thetas, false, false, 0, nullptr, true);
  expect_parity(st);
  EXPECT_LE(st.worst_prim, 5e-3);
}

TEST(GpuKernelOnHost, ThesisVariantMatchesItsCpuTwin) {
  const auto xs = case_study_states(40, 4);
  // In double the kernel code follows the CPU twin iterate for iterate.
  expect_parity(parity<double>(gpu::kThesis, 1, xs, false));
  // In float the same point comes out, but the literal algorithm's stopping test
  // (||Gamma|| <= 1e-3 after ~2,000 sublinear, restarted iterations) is reached
  // later: measured +34 % iterations on these QPs. Asserted as measured (at most
  // +50 %), not hidden: the exact variant has no such sensitivity.
  const ParityStats f = parity<float>(gpu::kThesis, 1, xs, false);
  expect_parity(f, false);
  EXPECT_GE(f.iters_gpu, 0.9 * f.iters_cpu);
  EXPECT_LE(f.iters_gpu, 1.5 * f.iters_cpu);
}

TEST(GpuKernelOnHost, ParallelTeamComputesWhatOneThreadDoes) {
  // Eight threads split every product and reduction as a thread block does.
  const auto xs = case_study_states(6, 5);
  const ParityStats one = parity<float>(gpu::kExact, 1, xs, false), eight = parity<float>(gpu::kExact, 8, xs, false);
  expect_parity(eight);
  test::expect_exact_twin(eight, 0);
  EXPECT_EQ(eight.iters_gpu, one.iters_gpu);  // the same iterations as one thread
  expect_parity(parity<float>(gpu::kExact, 3, xs, true));  // uneven split, warm start across solves
  expect_parity(parity<double>(gpu::kThesis, 4, case_study_states(2, 6), false));
}

TEST(GpuKernelOnHost, WarmStartOnAClosedLoopLikeSequence) {
  // States along a decaying trajectory: the shifted warm start of the kernel code
  // against the CPU twin's.
  std::vector<Eigen::VectorXd> xs;
  Eigen::VectorXd x = case_study_states(1, 7)[0];
  for (int k = 0; k < 60; ++k) {
    xs.push_back(x);
    x *= 0.97;
  }
  expect_parity(parity<float>(gpu::kExact, 1, xs, true));
}

TEST(GpuKernelOnHost, BlockFormOfTheConstraintMatrixGivesTheSameSolves) {
  // A = [I; P] from its repeating blocks (G_l = A^l B and their sums): what the kernel
  // uses where the dense matrices do not fit in shared memory (the TX2's 48 KB).
  const gpu::AdmmProblem p = make_gpu_problem(case_study_artifact().qp(), cpu_twin_options(SolverOptions{}));
  ASSERT_FALSE(p.Gblk.empty()) << "the case study's P has the move-blocked Toeplitz structure";
  EXPECT_LT(2 * p.Gblk.size(), p.A.size());  // less than half the numbers of the dense A
  const auto xs = case_study_states(100, 23);
  ParityStats st = parity<float>(gpu::kExact, 1, xs, false, true);
  expect_parity(st);
  EXPECT_LE(st.worst_prim, 5e-3);
  expect_parity(parity<float>(gpu::kExact, 5, case_study_states(6, 24), true, true));
  expect_parity(parity<double>(gpu::kThesis, 3, case_study_states(2, 25), false, true));
}

TEST(GpuKernelOnHost, InfeasibleInstancesAreCertifiedLikeOnTheCpu) {
  // States far out in the tightened box (30 %): most QPs have no feasible input.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs;
  const Eigen::VectorXd& hi = case_study_artifact().x_bar.hi;
  for (int k = 0; k < 20; ++k) {
    Eigen::VectorXd x(hi.size());
    for (Eigen::Index i = 0; i < hi.size(); ++i) x(i) = 0.3 * u(rng) * hi(i);
    xs.push_back(x);
  }
  // With the fixed penalty of the device the certificate needs ~12,000 iterations
  // (the CPU default's adaptive penalty: a few hundred), hence the larger limit. In
  // double the kernel code certifies what the CPU does, at the same iteration; in
  // float it does not fire at all (measured: y grows like k, so dy = y - y_prev
  // keeps ~1e-7 k / 5 relative precision, above eps_pinf = 1e-4 by k = 12,000): on
  // the device such QPs end at the iteration limit or the time budget.
  int infeasible = 0;
  const ParityStats st = parity<double>(gpu::kExact, 1, xs, false, false, 20000, &infeasible);
  EXPECT_EQ(st.status_mismatch, 0);
  EXPECT_NEAR(st.iters_gpu, st.iters_cpu, 0.1 * st.iters_cpu);
  EXPECT_GE(infeasible, 10) << "certified infeasible by the kernel code";
}

TEST(GpuKernelOnHost, NonFiniteDataEndsInNumericalFailure) {
  const MpcQpData d = case_study_artifact().qp();
  const SolverOptions o = cpu_twin_options(SolverOptions{});
  gpu::AdmmProblem p = make_gpu_problem(d, o);
  p.f0[0] = std::nanf("");
  HostKernelSolver<float> k(p, make_gpu_settings(o, gpu::kExact), 2);
  k.solve(case_study_states(1, 8)[0]);
  EXPECT_EQ(k.outcome().status, gpu::kNumericalFailure);
}

TEST(GpuKernelOnHost, TimeBudgetStopsTheLoop) {
  const MpcQpData d = case_study_artifact().qp();
  SolverOptions o = cpu_twin_options(SolverOptions{});
  o.time_budget_us = 1.0;
  o.eps_abs = 1e-12;
  o.eps_rel = 0.0;
  HostKernelSolver<float> k(make_gpu_problem(d, o), make_gpu_settings(o, gpu::kExact), 2);
  k.solve(case_study_states(1, 9)[0]);
  EXPECT_EQ(k.outcome().status, gpu::kTimeBudget);
}

TEST(GpuProblem, RejectsOptionsTheDeviceDoesNotImplement) {
  SolverOptions o;
  o.equilibrate = true;
  EXPECT_THROW(make_gpu_problem(case_study_artifact().qp(), o), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
