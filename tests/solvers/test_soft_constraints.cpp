// The softened QP (parametric_qp.hpp, soft_penalty.hpp): exact where the hard QP is
// feasible (the hard solution, no slack), the least violation where it is not; admm
// and reference agree on it (KKT residuals written from the definition); the other
// solvers say they do not solve it; the runtime flies the softened QP's solution every
// period, solving it only where it differs from the hard one (an infeasible hard QP,
// or multipliers past the penalty near the feasibility boundary).
#include <random>

#include <gtest/gtest.h>

#include "case_study_qps.hpp"
#include "tmpc/runtime/controller_solver.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/soft_penalty.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {
namespace {

// The noisy-sensor design: its configuration enables the soft constraints.
const ControllerArtifact& artifact() { return test::noisy_artifact(); }

TEST(SoftConstraints, TheLayoutIsTheHardQpWithOneSlackPerState) {
  MpcQpData d = artifact().qp();
  const ParametricQp hard = ParametricQp::from_mpc(d);
  d.soft_penalty = 7.0;
  const ParametricQp soft = ParametricQp::from_mpc(d);
  const int nu = hard.nz(), rows = d.N * d.n, nin = hard.nc() - rows;
  ASSERT_EQ(soft.slacks, d.n);
  ASSERT_EQ(soft.nz(), nu + d.n);
  ASSERT_EQ(soft.nc(), nin + 2 * rows + d.n);
  EXPECT_EQ(soft.H.topLeftCorner(nu, nu), hard.H);
  EXPECT_TRUE((soft.f0.tail(d.n).array() == 7.0).all());
  // Stage 3, state 5: upper row x - s_5 <= hi, lower row x + s_5 >= lo.
  const int up = nin + 3 * d.n + 5, low = nin + rows + 3 * d.n + 5;
  EXPECT_EQ(soft.A.row(up).head(nu), hard.A.row(nin + 3 * d.n + 5));
  EXPECT_EQ(soft.A(up, nu + 5), -1.0);
  EXPECT_EQ(soft.A(low, nu + 5), 1.0);
  EXPECT_EQ(soft.A.row(up).tail(d.n).cwiseAbs().sum(), 1.0);
  EXPECT_TRUE(std::isinf(soft.lo0(up)) && soft.lo0(up) < 0);
  EXPECT_EQ(soft.hi0(up), hard.hi0(nin + 3 * d.n + 5));
  EXPECT_TRUE(std::isinf(soft.hi0(low)) && soft.hi0(low) > 0);
  EXPECT_THROW(ParametricQp::soften(hard, d.N, d.n, 0.0), std::invalid_argument);
  // Solvers that do not solve this form say so.
  for (const char* name : {"cz", "admm-thesis"}) EXPECT_THROW(make_solver(name, d), std::invalid_argument) << name;
}

/// States along random rays at the given fractions of where the hard QP turns
/// infeasible (found by admm's certificate), from `seed`, as the QP's parameters (the
/// design's input-rate weight: with the steady previous input, v_prev = 0).
std::vector<Eigen::VectorXd> rays(const MpcQpData& d, int count, const std::vector<double>& fractions, unsigned seed) {
  SolverOptions o;
  o.warm_start = false;
  auto admm = make_solver("admm", d, o);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<Eigen::VectorXd> out;
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd dir = Eigen::VectorXd::Zero(d.parameters());
    for (int i = 0; i < d.n; ++i) dir(i) = normal(rng);
    dir /= dir.cwiseAbs().maxCoeff();
    double lo = 0.0, hi = 1.0;
    while (admm->solve(hi * dir).status == SolveStatus::Converged && hi < 1e3) hi *= 2.0;
    for (int it = 0; it < 20; ++it) {
      const double mid = 0.5 * (lo + hi);
      (admm->solve(mid * dir).status == SolveStatus::Converged ? lo : hi) = mid;
    }
    for (double f : fractions) out.push_back(f * (f < 1.0 ? lo : hi) * dir);
  }
  return out;
}

TEST(SoftConstraints, ThePenaltyIsExactOnOtherRaysAtTheCalibratedDepth) {
  // The artifact's penalty (calibrated at design, soft_penalty.hpp, at 0.1 to 0.3 of
  // the feasibility boundary) on other rays than the calibration's, over the same
  // fractions: the softened QP gives the hard optimum with no slack. (Nearer the
  // boundary the multiplier sums grow without bound and no finite penalty is exact:
  // the runtime solves the softened QP only where the hard one is infeasible.)
  const ControllerArtifact& a = artifact();
  ASSERT_GT(a.soft_penalty, 0.0) << "the shipped configuration enables soft constraints";
  const MpcQpData hard = a.qp(), soft = a.qp(false, true);
  SolverOptions o;
  o.warm_start = false;
  auto ref_hard = make_solver("reference", hard, o), ref_soft = make_solver("reference", soft, o);
  auto admm_soft = make_solver("admm", soft, o);
  double worst_slack = 0.0, worst_du = 0.0, worst_admm = 0.0;
  int n = 0;
  for (const Eigen::VectorXd& x : rays(hard, 40, {0.1, 0.2, 0.3}, 99)) {
    const SolveResult h = ref_hard->solve(x);
    ASSERT_EQ(h.status, SolveStatus::Converged);
    const SolveResult s = ref_soft->solve(x);
    ASSERT_EQ(s.status, SolveStatus::Converged);
    const SolveResult t = admm_soft->solve(x);
    ASSERT_EQ(t.status, SolveStatus::Converged);
    worst_slack = std::max(worst_slack, s.z.tail(soft.n).cwiseAbs().maxCoeff());
    worst_du = std::max(worst_du, (s.z.head(h.z.size()) - h.z).cwiseAbs().maxCoeff());
    worst_admm = std::max(worst_admm, (t.z - s.z).cwiseAbs().maxCoeff());
    ++n;
  }
  std::printf("%d feasible QPs up to 0.3 of the boundary: largest slack %.2e, |z_soft - z_hard| %.2e, admm vs "
              "reference %.2e (penalty %.4g)\n", n, worst_slack, worst_du, worst_admm, a.soft_penalty);
  EXPECT_LT(worst_slack, 1e-8);
  EXPECT_LT(worst_du, 1e-6);
  EXPECT_LT(worst_admm, 1e-6);
}

TEST(SoftConstraints, AnInfeasibleQpViolatesLeastAndTheSolversAgree) {
  const ControllerArtifact& a = artifact();
  const MpcQpData hard = a.qp(), soft = a.qp(false, true);
  SolverOptions o;
  o.warm_start = false;
  auto admm_hard = make_solver("admm", hard, o);
  auto ref_soft = make_solver("reference", soft, o), admm_soft = make_solver("admm", soft, o);
  int n = 0;
  for (const Eigen::VectorXd& x : rays(hard, 20, {1.5, 3.0}, 5)) {
    ASSERT_EQ(admm_hard->solve(x).status, SolveStatus::Infeasible);
    const SolveResult r = ref_soft->solve(x), s = admm_soft->solve(x);
    ASSERT_EQ(r.status, SolveStatus::Converged);
    ASSERT_EQ(s.status, SolveStatus::Converged);
    const CondensedQp qp = ref_soft->problem().instance(x);
    const KktResiduals kr = kkt_residuals(qp, r.z, r.y), ks = kkt_residuals(qp, s.z, s.y);
    const double scale = std::max(1.0, qp.f.cwiseAbs().maxCoeff());  // the penalty's size
    for (const KktResiduals& k : {kr, ks}) {
      EXPECT_LT(k.primal, 1e-9);
      EXPECT_LT(k.stationarity / scale, 1e-10);
      EXPECT_LT(k.complementarity / scale, 1e-10);
      EXPECT_LT(k.dual_sign / scale, 1e-10);
    }
    EXPECT_NEAR(qp_objective(qp, s.z), qp_objective(qp, r.z), 1e-8 * std::max(1.0, std::abs(qp_objective(qp, r.z))));
    EXPECT_GT(r.z.tail(soft.n).maxCoeff(), 1e-6);  // a slack is used
    // Inputs stay hard: inside the tightened input set.
    for (int i = 0; i < hard.M; ++i) {
      EXPECT_TRUE(hard.u_bar.contains(r.z.segment(i * hard.m, hard.m), 1e-9));
    }
    ++n;
  }
  EXPECT_EQ(n, 40);
}

TEST(SoftConstraints, TheRecoveryFliesTheSoftenedQpFromAnInfeasibleQpUntilItUsesNoSlack) {
  const ControllerArtifact& a = artifact();
  SolverOptions o;
  o.warm_start = false;
  auto rec = make_controller_solver("active-set", a, o, "", false);
  auto hard = make_solver("active-set", a.qp(), o);
  auto soft = make_solver("reference", a.qp(false, true), o);  // the oracle of the softened QP
  // Feasible (0.5 of a ray's boundary) and infeasible (2.0) states in turn.
  const std::vector<Eigen::VectorXd> xs = rays(a.qp(), 10, {0.5, 2.0}, 17);
  int softened = 0, stayed = 0;
  bool soft_mode = false;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const SolveResult& h = hard->solve(xs[k]);
    const SolveStatus hs = h.status;
    const Eigen::VectorXd hz = h.z;
    const SolveResult& sr = soft->solve(xs[k]);
    ASSERT_EQ(sr.status, SolveStatus::Converged);
    const Eigen::VectorXd sz = sr.z.head(hz.size());
    const double s_slack = sr.z.tail(soft->problem().slacks).maxCoeff();
    const SolveResult& r = rec->solve(xs[k]);
    EXPECT_EQ(r.status, SolveStatus::Converged);
    EXPECT_EQ(r.z.size(), hz.size());  // the hard layout
    if (hs == SolveStatus::Infeasible || soft_mode) {
      // Softened: the softened QP's solution (the reference's), its slack reported.
      EXPECT_TRUE(r.softened) << k;
      EXPECT_LT((r.z - sz).cwiseAbs().maxCoeff(), 1e-7) << k;
      EXPECT_NEAR(r.slack_max, s_slack, 1e-7) << k;
      if (hs == SolveStatus::Infeasible) EXPECT_GT(r.slack_max, 1e-6) << k;
      if (hs != SolveStatus::Infeasible) ++stayed;
      // No slack: the softened solution is the hard QP's optimum.
      if (hs != SolveStatus::Infeasible && r.slack_max <= 1e-9) EXPECT_LT((r.z - hz).cwiseAbs().maxCoeff(), 1e-7) << k;
      ++softened;
    } else {
      EXPECT_FALSE(r.softened) << k;
      EXPECT_LT((r.z - hz).cwiseAbs().maxCoeff(), 1e-9) << k;
    }
    soft_mode = r.softened && r.slack_max > 1e-9;
  }
  // Each infeasible state is followed by a feasible one at half its ray's boundary,
  // which the softened QP flies (the penalty is exact there: no slack, the hard optimum).
  EXPECT_EQ(softened, 19);
  EXPECT_EQ(stayed, 9);
  // Calibration: the penalty covers the sampled multipliers with the safety factor.
  const SoftPenaltyCalibration c = calibrate_soft_penalty(a, 10.0, 10, 3);
  EXPECT_EQ(c.samples, 30);  // 0.1 to 0.3 of a feasible ray: all feasible (convex set)
  EXPECT_GT(c.largest_multiplier_sum, 0.0);
  EXPECT_DOUBLE_EQ(c.penalty, std::max(1.0, 10.0 * c.largest_multiplier_sum));
}

// Near the hard QP's feasibility boundary (0.9 to 0.99 of a ray's) its multipliers
// grow past the penalty, which is calibrated at 0.1 to 0.3 (soft_penalty.hpp): there the
// softened optimum takes a slack instead of the hard solution's extreme inputs, and
// the runtime's law is that optimum although the hard QP is feasible. The oracles, apart
// from the law: the softened QP solved by the reference solver, and the criterion from
// the hard QP's multipliers (the reference solver's): a slack is used exactly where
// some state's multipliers summed over the horizon pass the penalty.
TEST(SoftConstraints, NearTheBoundaryTheLawIsTheSoftenedOptimumNotTheHardExtreme) {
  const ControllerArtifact& a = artifact();
  SolverOptions o;
  o.warm_start = false;
  const MpcQpData d = a.qp();
  auto hard = make_solver("reference", d, o);
  auto soft = make_solver("reference", a.qp(false, true), o);
  const int nz = d.variables(), m = d.m;
  int inside = 0, past = 0;
  double largest_gap = 0.0;  // |u_hard - u_soft| where they differ: what the law avoids
  int beyond_boundary = 0;
  for (const Eigen::VectorXd& x : rays(d, 8, {0.2, 0.9, 0.97, 0.99}, 31)) {
    const SolveResult& h = hard->solve(x);
    if (h.status == SolveStatus::Infeasible) {  // admm's boundary is found to its tolerance
      ++beyond_boundary;
      continue;
    }
    ASSERT_EQ(h.status, SolveStatus::Converged);
    const Eigen::VectorXd hz = h.z;
    double sum_max = 0.0;
    for (int i = 0; i < d.n; ++i) {
      double sum = 0.0;
      for (int k = 0; k < d.N; ++k) sum += std::abs(h.y(nz + k * d.n + i));
      sum_max = std::max(sum_max, sum);
    }
    const SolveResult& sr = soft->solve(x);
    ASSERT_EQ(sr.status, SolveStatus::Converged);
    const Eigen::VectorXd sz = sr.z.head(nz);
    const double slack = sr.z.tail(d.n).maxCoeff();
    const bool beyond = sum_max > a.soft_penalty * (1.0 + 1e-6);
    if (std::abs(sum_max / a.soft_penalty - 1.0) > 1e-3) EXPECT_EQ(slack > 1e-9, beyond) << sum_max;
    auto law = make_controller_solver("active-set", a, o, "", false);
    const SolveResult& r = law->solve(x);
    ASSERT_EQ(r.status, SolveStatus::Converged);
    EXPECT_LT((r.z - sz).cwiseAbs().maxCoeff(), 1e-6) << "the law is the softened optimum";
    EXPECT_EQ(r.softened, slack > 1e-9);
    if (r.softened) {
      EXPECT_TRUE(r.hard_solved);  // feasible: softened for its multipliers, not infeasibility
      EXPECT_NEAR(r.slack_max, slack, 1e-6);
      largest_gap = std::max(largest_gap, (hz - sz).head(m).cwiseAbs().maxCoeff());
      ++past;
    } else {
      EXPECT_LT((r.z - hz).cwiseAbs().maxCoeff(), 1e-6) << "below the penalty: the hard solution";
      ++inside;
    }
  }
  std::printf("%d states below the penalty, %d past it, %d infeasible; the hard first input differs by up to %.3g "
              "(normalized)\n", inside, past, beyond_boundary, largest_gap);
  EXPECT_LE(beyond_boundary, 4);
  EXPECT_EQ(inside, 8);  // the 0.2 states (README)
  EXPECT_EQ(past, 24);   // every state at 0.9 to 0.99
  EXPECT_NEAR(largest_gap, 0.199, 0.02);
}

// Along a path from an infeasible state back into the feasible set (s x_b, s from 1.3
// down to 0.3, x_b where a ray turns infeasible), the recovery's first input moves in
// steps of the path's size: no jump where the hard QP becomes feasible again (the
// softened QP flies until it uses no slack, and there it is the hard optimum). The
// oracle: the hard and softened QPs solved apart; switching back to the hard QP at its
// feasibility boundary instead jumps, and the test measures by how much.
TEST(SoftConstraints, TheRecoveryIsContinuousWhereTheHardQpBecomesFeasibleAgain) {
  const ControllerArtifact& a = artifact();
  SolverOptions o;
  o.warm_start = false;
  auto hard = make_solver("active-set", a.qp(), o);
  auto soft = make_solver("active-set", a.qp(false, true), o);
  const int m = a.qp().m;
  double worst_ratio = 0.0, switch_ratio = 0.0;
  for (const Eigen::VectorXd& xb : rays(a.qp(), 6, {1.0}, 23)) {
    auto rec = make_controller_solver("active-set", a, o, "", false);
    Eigen::VectorXd u_prev, u_switch_prev;
    double largest = 0.0, typical = 0.0, largest_switch = 0.0;
    int steps = 0, exit_step = -1;
    for (int i = 0; i <= 100; ++i) {
      const Eigen::VectorXd x = (1.3 - 0.01 * i) * xb;
      const SolveResult& r = rec->solve(x);
      ASSERT_EQ(r.status, SolveStatus::Converged);
      const Eigen::VectorXd u = r.z.head(m);
      if (!r.softened && exit_step < 0) exit_step = i;
      // The policy without the hysteresis: the hard QP wherever it is feasible.
      const SolveResult& h = hard->solve(x);
      const Eigen::VectorXd us = h.status == SolveStatus::Converged ? Eigen::VectorXd(h.z.head(m)) : Eigen::VectorXd(soft->solve(x).z.head(m));
      if (i > 0) {
        const double du = (u - u_prev).cwiseAbs().maxCoeff();
        largest = std::max(largest, du);
        typical += du;
        ++steps;
        largest_switch = std::max(largest_switch, (us - u_switch_prev).cwiseAbs().maxCoeff());
      }
      u_prev = u;
      u_switch_prev = us;
    }
    ASSERT_GT(exit_step, 0) << "the recovery never returned to the hard QP";
    typical /= steps;
    worst_ratio = std::max(worst_ratio, largest / typical);
    switch_ratio = std::max(switch_ratio, largest_switch / typical);
  }
  std::printf("largest step of the first input over the mean step: %.2f with the recovery's hysteresis, %.2f switching "
              "back at the feasibility boundary\n", worst_ratio, switch_ratio);
  // A piecewise-affine law: its slope changes with the active set (measured 7.7); the
  // switch at the boundary jumps by thousands of mean steps (measured 5519).
  EXPECT_LT(worst_ratio, 20.0);
  EXPECT_GT(switch_ratio, 100.0);  // the oracle sees a jump where there is one
}

}  // namespace
}  // namespace tmpc
