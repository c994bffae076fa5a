// Solvers against the definition of optimality (KKT residuals computed here) and
// against each other: 500 case-study QPs and random small MPC QPs.
#include <algorithm>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "case_study_qps.hpp"
#include "tmpc/sets/lp.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {
namespace {

const ControllerArtifact& artifact() { return test::case_study_artifact(); }
using test::case_study_states;

double rel_stationarity(const CondensedQp& qp, const Eigen::VectorXd& z, const Eigen::VectorXd& y) {
  const double scale = std::max({(qp.H * z).cwiseAbs().maxCoeff(), qp.f.cwiseAbs().maxCoeff(),
                                 (qp.A.transpose() * y).cwiseAbs().maxCoeff(), 1.0});
  return kkt_residuals(qp, z, y).stationarity / scale;
}

TEST(Solvers, FiveHundredCaseStudyQps) {
  SolverOptions o;
  o.warm_start = false;
  auto ref = make_solver("reference", artifact(), o);
  auto admm = make_solver("admm", artifact(), o);
  auto cz = make_solver("cz", artifact(), o);
  auto thesis = make_solver("admm-thesis", artifact(), o);
  double worst_ref = 0, worst_admm_u = 0, worst_cz_u = 0, worst_admm_stat = 0, worst_admm_prim = 0;
  double worst_gap = 0, max_gap_thesis = 0, min_gap_thesis = 1e300, worst_thesis_u = 0;
  int n = 0, most_admm_iterations = 0;
  const MpcQpData data = artifact().qp();
  for (const Eigen::VectorXd& x0 : case_study_states(500, 3)) {
    // Full cost V = objective + x0' Q' W_x Q x0 >= 0: the scale for relative gaps.
    const double V_scale = std::max(1e-9, condensed_qp(data, x0).constant);
    const SolveResult r = ref->solve(x0);
    ASSERT_EQ(r.status, SolveStatus::Converged) << to_string(r.status) << " at instance " << n;
    const CondensedQp qp = ref->problem().instance(x0);
    const KktResiduals kr = kkt_residuals(qp, r.z, r.y);
    if (kr.max() > worst_ref) {
      worst_ref = kr.max();
      if (worst_ref > 1e-9) std::printf("reference KKT at %d: stat %.2e prim %.2e comp %.2e\n", n, kr.stationarity, kr.primal, kr.complementarity);
    }
    const SolveResult a = admm->solve(x0);
    ASSERT_EQ(a.status, SolveStatus::Converged);
    most_admm_iterations = std::max(most_admm_iterations, a.iterations);
    worst_admm_u = std::max(worst_admm_u, (a.u0() - r.u0()).cwiseAbs().maxCoeff());
    worst_admm_stat = std::max(worst_admm_stat, rel_stationarity(qp, a.z, a.y));
    worst_admm_prim = std::max(worst_admm_prim, kkt_residuals(qp, a.z, a.y).primal);
    worst_gap = std::max(worst_gap, std::abs(a.objective - r.objective) / (r.objective + V_scale));
    // Every 10th instance through the slower CZ and thesis solvers.
    if (n % 10 == 0) {
      const SolveResult c = cz->solve(x0);
      ASSERT_EQ(c.status, SolveStatus::Converged);
      worst_cz_u = std::max(worst_cz_u, (c.u0() - r.u0()).cwiseAbs().maxCoeff());
      EXPECT_LT(kkt_residuals(qp, c.z, Eigen::VectorXd::Zero(qp.A.rows())).primal, 1e-2);
      const SolveResult t = thesis->solve(x0);
      const double gap = (t.objective - r.objective) / (r.objective + V_scale);
      max_gap_thesis = std::max(max_gap_thesis, gap);
      min_gap_thesis = std::min(min_gap_thesis, gap);
      worst_thesis_u = std::max(worst_thesis_u, (t.u0() - r.u0()).cwiseAbs().maxCoeff());
    }
    ++n;
  }
  std::printf("reference KKT %.2e; admm |du0| %.2e, rel. stationarity %.2e, primal %.2e, gap %.2e; cz |du0| %.2e; "
              "thesis gap [%.2e, %.2e], |du0| %.2e\n",
              worst_ref, worst_admm_u, worst_admm_stat, worst_admm_prim, worst_gap, worst_cz_u, min_gap_thesis,
              max_gap_thesis, worst_thesis_u);
  // README: the reference's KKT residuals below 1e-10; the default admm exact (its
  // active-set finish: KKT residuals at rounding level, the reference's optimum), every
  // case-study QP ending at the first check (5 iterations); CZ to its tolerance.
  EXPECT_LT(worst_ref, 1e-10);
  EXPECT_LT(worst_admm_u, 1e-6);
  EXPECT_LT(worst_admm_stat, 1e-9);
  EXPECT_LT(worst_admm_prim, 1e-9);
  EXPECT_LT(worst_gap, 1e-9);  // of the full cost V
  EXPECT_EQ(most_admm_iterations, 5);
  EXPECT_LT(worst_cz_u, 1e-2);
  // The thesis variant (E3, documented): it stops on ||Gamma|| alone and its u-step is
  // the clipped unconstrained minimizer of a dense H1, so its objective is not the
  // optimum: gaps from about 1e-5 to 1e-2 of the cost, u(0) off by up to about 1e-2.
  EXPECT_GT(max_gap_thesis, 1e-3);  // README: about 2e-3 of the cost at epsilon = 1e-3
  EXPECT_LT(max_gap_thesis, 5e-3);
  EXPECT_GT(min_gap_thesis, -5e-3);  // never better than the optimum beyond tolerance
  EXPECT_LT(worst_thesis_u, 5e-2);
}

// README: every case-study QP at N = 10, 20, 40, cold and warm, ends at the first check.
TEST(Solvers, ExactAdmmEndsAtItsFirstCheckAtEveryHorizon) {
  const ControllerArtifact& a = artifact();
  for (int N : {10, 20, 40}) {
    const MpcQpData d = build_mpc_qp(a.A, a.B, a.Sigma_rho, a.Sigma_lambda, a.L, a.x_bar, a.u_bar, N, 4);
    for (bool warm : {false, true}) {
      SolverOptions o;
      o.warm_start = warm;
      auto admm = make_solver("admm", d, o);
      int most = 0;
      for (const Eigen::VectorXd& x0 : case_study_states(100, 17)) {
        const SolveResult& r = admm->solve(x0);
        ASSERT_EQ(r.status, SolveStatus::Converged) << "N = " << N;
        most = std::max(most, r.iterations);
      }
      EXPECT_EQ(most, o.check_every) << "N = " << N << (warm ? ", warm" : ", cold");
    }
  }
}

// The offset-free form (artifact.qp(true)): a force on the load up to 1 N, a small
// model offset c, nominal states around the force's steady state. Every solver
// against the reference, whose KKT residuals are checked on the shifted instance.
TEST(Solvers, OffsetFreeQpsAgreeWithTheReference) {
  SolverOptions o;
  o.warm_start = false;
  const MpcQpData data = artifact().qp(true);
  ASSERT_EQ(data.parameters(), 24 + 3 + 24);
  auto ref = make_solver("reference", data, o);
  auto admm = make_solver("admm", data, o);
  auto cz = make_solver("cz", data, o);
  auto thesis = make_solver("admm-thesis", data, o);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_ref = 0, worst_admm_u = 0, worst_cz_u = 0, worst_thesis_box = 0, worst_shift = 0;
  int n = 0;
  for (const Eigen::VectorXd& x0 : case_study_states(60, 9)) {
    Eigen::VectorXd theta(data.parameters());
    const Eigen::Vector3d d(u(rng), u(rng), u(rng));
    Eigen::VectorXd c(24);
    for (int i = 0; i < 24; ++i) c(i) = 1e-5 * u(rng);
    theta << x0, d, c;
    const SolveResult r = ref->solve(theta);
    ASSERT_EQ(r.status, SolveStatus::Converged) << to_string(r.status) << " at instance " << n;
    const CondensedQp qp = ref->problem().instance(theta);
    worst_ref = std::max(worst_ref, kkt_residuals(qp, r.z, r.y).max());
    // The shift is real: the input bounds moved by u_s = Tu d.
    worst_shift = std::max(worst_shift, (qp.lo.head(4) - data.u_bar.lo).cwiseAbs().maxCoeff());
    const SolveResult a = admm->solve(theta);
    ASSERT_EQ(a.status, SolveStatus::Converged);
    worst_admm_u = std::max(worst_admm_u, (a.u0() - r.u0()).cwiseAbs().maxCoeff());
    const SolveResult z = cz->solve(theta);
    ASSERT_EQ(z.status, SolveStatus::Converged);
    worst_cz_u = std::max(worst_cz_u, (z.u0() - r.u0()).cwiseAbs().maxCoeff());
    const SolveResult t = thesis->solve(theta);
    EXPECT_NE(t.status, SolveStatus::InvalidInput);
    // The thesis variant clips u to the shifted input box.
    const Eigen::VectorXd tz = qp.A.topRows(t.z.size()) * t.z;
    worst_thesis_box = std::max({worst_thesis_box, (qp.lo.head(t.z.size()) - tz).maxCoeff(),
                                 (tz - qp.hi.head(t.z.size())).maxCoeff()});
    ++n;
  }
  std::printf("offset-free: reference KKT %.2e, admm |du0| %.2e, cz |du0| %.2e, thesis box %.2e, shift %.3f\n", worst_ref,
              worst_admm_u, worst_cz_u, worst_thesis_box, worst_shift);
  EXPECT_LT(worst_ref, 1e-10);
  EXPECT_LT(worst_admm_u, 1e-6);  // exact (README), as on the nominal QPs
  EXPECT_LT(worst_cz_u, 1e-2);
  EXPECT_LE(worst_thesis_box, 1e-12);
  EXPECT_GT(worst_shift, 1e-3);
  // A parameter of the nominal size is refused, not misread.
  EXPECT_EQ(admm->solve(Eigen::VectorXd::Zero(24)).status, SolveStatus::InvalidInput);
  EXPECT_EQ(thesis->solve(Eigen::VectorXd::Zero(24)).status, SolveStatus::InvalidInput);
}

MpcQpData random_mpc(std::mt19937_64& rng, int n, int m, int N, int M) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n, n), B(n, m);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) A(i, j) = 0.3 * g(rng);
    for (int j = 0; j < m; ++j) B(i, j) = g(rng);
  }
  A += 0.9 * Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd R = 0.1 * Eigen::MatrixXd::Identity(m, m);
  return build_mpc_qp(A, B, Q, R, 5.0 * Q, Box::symmetric(Eigen::VectorXd::Ones(n)),
                      Box::symmetric(0.5 * Eigen::VectorXd::Ones(m)), N, M);
}

TEST(Solvers, RandomSmallMpcQps) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0, cz_converged = 0;
  for (int p = 0; p < 20; ++p) {
    const MpcQpData d = random_mpc(rng, 3, 2, 8, 4);
    SolverOptions o;
    o.warm_start = false;
    o.eps_abs = o.eps_rel = 1e-5;
    auto ref = make_solver("reference", d, o);
    auto admm = make_solver("admm", d, o);
    auto cz = make_solver("cz", d, o);
    for (int k = 0; k < 10; ++k) {
      Eigen::VectorXd x0(3);
      for (int i = 0; i < 3; ++i) x0(i) = 0.5 * u(rng);
      const SolveResult r = ref->solve(x0);
      if (r.status != SolveStatus::Converged) continue;  // infeasible instance
      const CondensedQp qp = ref->problem().instance(x0);
      EXPECT_LT(kkt_residuals(qp, r.z, r.y).max(), 1e-8);
      // eps = 1e-5 on the residuals: the cost is optimal to about that (these random
      // problems are flat in some directions, so the minimizer itself is not compared).
      const SolveResult a = admm->solve(x0);
      EXPECT_EQ(a.status, SolveStatus::Converged);
      EXPECT_LT(std::abs(a.objective - r.objective) / std::max(1.0, std::abs(r.objective)), 1e-4);
      EXPECT_LT(kkt_residuals(qp, a.z, a.y).primal, 1e-3);
      const SolveResult c = cz->solve(x0);
      if (c.status == SolveStatus::Converged) {
        ++cz_converged;
        EXPECT_LT(std::abs(c.objective - r.objective) / std::max(1.0, std::abs(r.objective)), 1e-3);
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
  EXPECT_GE(cz_converged, checked * 9 / 10) << "CZ converged on " << cz_converged << " of " << checked;
}

// The issue asks for "never worse than cold" in iterations on a shifted closed-loop
// sequence. ADMM alone gives no per-step guarantee (it failed on a few steps by one or
// two check intervals before the active-set finish); with the finish both end at the
// first check, and the warm guess needs fewer active-set steps in total.
TEST(Solvers, WarmStartBeatsColdOnAClosedLoopSequence) {
  const ControllerArtifact& a = artifact();
  SolverOptions warm_o, cold_o;
  cold_o.warm_start = false;
  auto warm = make_solver("admm", a, warm_o);
  auto cold = make_solver("admm", a, cold_o);
  Eigen::VectorXd x = case_study_states(1, 8)[0];
  int warm_total = 0, cold_total = 0, worse = 0, worst_excess = 0, warm_steps = 0, cold_steps = 0;
  for (int k = 0; k < 100; ++k) {
    const SolveResult w = warm->solve(x);
    const SolveResult c = cold->solve(x);
    ASSERT_EQ(w.status, SolveStatus::Converged);
    if (w.iterations > c.iterations) {
      ++worse;
      worst_excess = std::max(worst_excess, w.iterations - c.iterations);
    }
    warm_total += w.iterations;
    cold_total += c.iterations;
    warm_steps += w.active_set_steps;
    cold_steps += c.active_set_steps;
    x = a.A * x + a.B * w.u0();  // nominal closed loop
  }
  std::printf("100 closed-loop steps: warm %d iterations (%d active-set steps), cold %d (%d); warm worse on %d steps "
              "(by at most %d)\n",
              warm_total, warm_steps, cold_total, cold_steps, worse, worst_excess);
  EXPECT_EQ(worse, 0);
  EXPECT_LE(warm_total, cold_total);
  EXPECT_LE(warm_steps, cold_steps);
}

// The crash start (the active set of the start point, active-set steps) returns a KKT
// point or hands over to the ADMM: either way the reference's solution, cold on 500
// case-study QPs and warm along a closed loop.
TEST(Solvers, CrashStartGivesTheReferenceSolution) {
  const ControllerArtifact& a = artifact();
  SolverOptions o;
  o.warm_start = false;
  o.crash_start = true;
  auto crash = make_solver("admm", a, o);
  auto ref = make_solver("reference", a, SolverOptions{});
  int crashed = 0;
  double worst_u = 0.0;
  for (const Eigen::VectorXd& x0 : case_study_states(500, 21)) {
    const SolveResult r = ref->solve(x0);
    const SolveResult c = crash->solve(x0);
    ASSERT_EQ(c.status, SolveStatus::Converged);
    crashed += c.iterations == 0;
    worst_u = std::max(worst_u, (c.u0() - r.u0()).cwiseAbs().maxCoeff());
    const CondensedQp qp = ref->problem().instance(x0);
    // A crash is an exact KKT point; a hand-over ends at the ADMM's tolerance.
    EXPECT_LT(kkt_residuals(qp, c.z, c.y).primal, c.iterations == 0 ? 1e-6 : 5e-3);
  }
  std::printf("crash start: %d of 500 cold QPs solved before any ADMM iteration; worst |du| %.2e\n", crashed, worst_u);
  EXPECT_LT(worst_u, 1e-3);
  o.warm_start = true;
  auto warm = make_solver("admm", a, o);
  Eigen::VectorXd x = case_study_states(1, 22)[0];
  int warm_crashed = 0;
  for (int k = 0; k < 100; ++k) {
    const SolveResult w = warm->solve(x);
    ASSERT_EQ(w.status, SolveStatus::Converged);
    warm_crashed += w.iterations == 0;
    EXPECT_LT((w.u0() - ref->solve(x).u0()).cwiseAbs().maxCoeff(), 1e-3);
    x = a.A * x + a.B * w.u0();
  }
  std::printf("crash start, warm: %d of 100 closed-loop steps without an ADMM iteration\n", warm_crashed);
  EXPECT_GT(warm_crashed, 50);
}

// Infeasible instances end with status infeasible (OSQP's certificate), checked
// against an LP feasibility test of lo <= A z <= hi (CLP: shares no code with ADMM):
// every certificate is right, and no infeasible instance runs to the iteration limit.
TEST(Solvers, ExactAdmmCertifiesInfeasibility) {
  const ControllerArtifact& a = artifact();
  SolverOptions o;
  o.warm_start = false;
  auto admm = make_solver("admm", a, o);
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int infeasible = 0, certified = 0, most = 0, borderline = 0;
  for (int k = 0; k < 60; ++k) {
    Eigen::VectorXd x0(24);  // 3 % to 30 % of the box at once: many without any feasible input
    const double scale = 0.03 + 0.27 * (k % 10) / 9.0;
    for (int i = 0; i < 24; ++i) x0(i) = scale * u(rng) * a.x_bar.hi(i);
    const CondensedQp qp = admm->problem().instance(x0);
    // The largest common slack t of lo <= A z <= hi (z free, t <= 1): feasible when
    // t* > 0, infeasible when t* < 0; within 1e-7 of 0 CLP's own tolerance decides, so
    // such a borderline instance is counted apart, not scored.
    const double slack = largest_common_slack(qp.A, qp.lo, qp.hi);
    ASSERT_TRUE(std::isfinite(slack)) << "the feasibility LP failed";
    if (std::abs(slack) < 1e-7) {
      ++borderline;
      continue;
    }
    const SolveResult r = admm->solve(x0);
    if (slack < 0.0) {
      ++infeasible;
      EXPECT_EQ(r.status, SolveStatus::Infeasible) << "instance " << k << ": " << to_string(r.status);
      certified += r.status == SolveStatus::Infeasible;
      most = std::max(most, r.iterations);
    } else {
      EXPECT_EQ(r.status, SolveStatus::Converged) << "instance " << k << " is feasible";
    }
  }
  std::printf("%d of 60 instances infeasible (LP), %d certified by the ADMM, in at most %d iterations; %d borderline\n",
              infeasible, certified, most, borderline);
  // README: all infeasible instances of this set (36 of 60) certified at the first check.
  EXPECT_LE(borderline, 2);
  EXPECT_NEAR(infeasible, 36, 2);
  EXPECT_EQ(certified, infeasible);
  EXPECT_EQ(most, 5);
}

TEST(Solvers, StatusesForBadInputAndTimeBudget) {
  SolverOptions o;
  o.warm_start = false;
  o.time_budget_us = 1e-3;  // expires at the first check
  o.check_every = 1;
  for (const char* name : {"admm", "admm-thesis", "cz", "reference", "active-set"}) {
    auto s = make_solver(name, artifact(), o);
    Eigen::VectorXd bad = Eigen::VectorXd::Zero(24);
    bad(3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(s->solve(bad).status, SolveStatus::InvalidInput) << name;
    EXPECT_EQ(s->solve(Eigen::VectorXd::Zero(5)).status, SolveStatus::InvalidInput) << name;
    EXPECT_EQ(s->solve(case_study_states(1, 9)[0]).status, SolveStatus::TimeBudget) << name;
  }
  EXPECT_THROW(make_solver("gurobi", artifact()), std::invalid_argument);
  SolverOptions bad;
  bad.r = 1.5;
  EXPECT_THROW(make_solver("admm", artifact(), bad), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
