// The parametric dual active-set solver ("active-set") and the redundant-row
// certificate, against oracles that share no code with them: the reference interior
// point, KKT residuals of the full QP (every row, the dropped ones too), CLP's LPs for
// feasibility, and a hand-made QP whose redundant rows are known.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "case_study_qps.hpp"
#include "tmpc/qp/redundant_rows.hpp"
#include "tmpc/sets/lp.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {
namespace {

const ControllerArtifact& artifact() { return test::case_study_artifact(); }

/// The largest common slack of the instance's rows (CLP): > 0 feasible.
double feasibility_slack(const CondensedQp& qp) { return largest_common_slack(qp.A, qp.lo, qp.hi); }

/// Hard states: along random directions, at 50-95 % of the largest feasible scale
/// (bisection on the LP above), as the solver issue defines them.
std::vector<Eigen::VectorXd> hard_states(const ParametricQp& qp, const Eigen::VectorXd& half_width, int count,
                                         unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> frac(0.5, 0.95);
  std::vector<Eigen::VectorXd> xs;
  while (static_cast<int>(xs.size()) < count) {
    Eigen::VectorXd dir(half_width.size());
    for (Eigen::Index i = 0; i < dir.size(); ++i) dir(i) = g(rng) * half_width(i);
    dir /= dir.cwiseQuotient(half_width).cwiseAbs().maxCoeff();  // on the box's boundary at scale 1
    double lo = 0.0, hi = 1.0;
    if (feasibility_slack(qp.instance(hi * dir)) > 0.0) continue;  // feasible everywhere along it
    for (int it = 0; it < 30; ++it) {
      const double mid = 0.5 * (lo + hi);
      (feasibility_slack(qp.instance(mid * dir)) > 0.0 ? lo : hi) = mid;
    }
    xs.push_back(frac(rng) * lo * dir);
  }
  return xs;
}

double rel_kkt(const CondensedQp& qp, const SolveResult& r) {
  const KktResiduals k = kkt_residuals(qp, r.z, r.y);
  // Stationarity relative to its largest term (the multipliers reach 1e3 on hard states).
  const double scale = std::max({(qp.H * r.z).cwiseAbs().maxCoeff(), qp.f.cwiseAbs().maxCoeff(),
                                 (qp.A.transpose() * r.y).cwiseAbs().maxCoeff(), 1.0});
  return std::max({k.stationarity / scale, k.primal, k.complementarity, k.dual_sign});
}

MpcQpData certified(MpcQpData d) {
  if (d.offset_free()) {
    // The estimates the offset-free certificate covers: 3 N of force, the residual
    // within W's box.
    const Eigen::VectorXd c_max = artifact().W.G.cwiseAbs().rowwise().sum() + artifact().W.c.cwiseAbs();
    certify_redundant_rows(d, Eigen::VectorXd::Constant(d.disturbances(), 3.0), c_max);
  } else {
    certify_redundant_rows(d);
  }
  return d;
}

TEST(ActiveSet, RedundantRowsOfAHandMadeQp) {
  // z in R^2, theta in R^1 with |theta| <= 1:
  //   row 0: -1 <= z1 <= 1        row 1: -1 <= z2 <= 1
  //   row 2: -3 <= z1 + z2 <= 3   (implied by rows 0 and 1)
  //   row 3: -1 <= z1 <= 1        (a copy of row 0: one of them stays)
  //   row 4: -2 <= z1 + theta <= 2 (implied over the domain only)
  //   row 5: -1 <= z1 - z2 <= 1   (binds)
  ParametricQp qp;
  qp.H = Eigen::Matrix2d::Identity();
  qp.F = Eigen::MatrixXd::Zero(2, 1);
  qp.f0 = Eigen::Vector2d(1.0, -1.0);
  qp.A.resize(6, 2);
  qp.A << 1, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, -1;
  qp.E = Eigen::MatrixXd::Zero(6, 1);
  qp.E(4, 0) = 1.0;
  qp.lo0.resize(6);
  qp.hi0.resize(6);
  qp.lo0 << -1, -1, -3, -1, -2, -1;
  qp.hi0 << 1, 1, 3, 1, 2, 1;
  ParameterDomain dom{Eigen::MatrixXd::Identity(1, 1), Eigen::VectorXd::Constant(1, -1.0), Eigen::VectorXd::Ones(1)};
  const RedundancyReport rep = redundant_rows(qp, dom);
  EXPECT_TRUE(rep.complete);
  EXPECT_EQ(rep.rows, (std::vector<int>{0, 2, 4}));  // row 0 goes, its copy (row 3) stays
  // A wider domain keeps row 4.
  dom.lo(0) = -1.5;
  dom.hi(0) = 1.5;
  EXPECT_EQ(redundant_rows(qp, dom).rows, (std::vector<int>{0, 2}));
  // A certificate that does not fit the QP is refused, naming what is wrong.
  try {
    make_active_set_solver(qp, SolverOptions{}, {9}, dom);
    ADD_FAILURE() << "row 9 of a 6-row QP accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("redundant row 9 of a QP with 6 rows"), std::string::npos) << e.what();
  }
  ParameterDomain wide{Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2)};
  EXPECT_THROW(make_active_set_solver(qp, SolverOptions{}, {0}, wide), std::invalid_argument);
  // An empty feasible set is an error, not a list.
  qp.lo0(0) = 2.0;
  qp.hi0(0) = 3.0;
  EXPECT_THROW(redundant_rows(qp, dom), std::invalid_argument);
}

TEST(ActiveSet, RowsWithinTheSinglePrecisionScreensBandAreDecidedInDouble) {
  // min 1/2 |z|^2 - theta'z s.t. -1 <= z_1 <= 1, -1 <= z_2 <= 0.7: u = theta, placed
  // within 1e-9 of a bound, inside and outside, far inside float's rounding (1e-7 here).
  ParametricQp qp;
  qp.H = Eigen::Matrix2d::Identity();
  qp.F = -Eigen::Matrix2d::Identity();
  qp.f0 = Eigen::Vector2d::Zero();
  qp.A = Eigen::Matrix2d::Identity();
  qp.E = Eigen::Matrix2d::Zero();
  qp.lo0 = Eigen::Vector2d::Constant(-1.0);
  qp.hi0 = Eigen::Vector2d(1.0, 0.7);
  SolverOptions o;
  o.warm_start = false;
  auto s = make_reference_solver(qp, o);  // the oracle
  auto as = make_active_set_solver(qp, o);
  for (double delta : {-1e-9, 1e-9, -1e-8, 1e-8}) {  // past the 2e-10 feasibility tolerance
    const Eigen::Vector2d theta(1.0 + delta, 0.3);
    const SolveResult& r = as->solve(theta);
    ASSERT_EQ(r.status, SolveStatus::Converged) << delta;
    EXPECT_EQ(r.z(0), std::min(1.0, 1.0 + delta)) << delta;
    EXPECT_EQ(r.y(0) > 0.0, delta > 0.0) << delta;
    EXPECT_NEAR(r.z(1), 0.3, 1e-15);
    EXPECT_LT((r.z - s->solve(theta).z).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(ActiveSet, ExactOnBenchAndHardStatesWithTheRedundantRowsLeftOut) {
  const MpcQpData plain = artifact().qp();
  const auto t0 = std::chrono::steady_clock::now();
  const MpcQpData d = certified(plain);
  std::printf("certificate: %.2f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  // The artifact records the same rows (make_artifact certifies them).
  EXPECT_EQ(artifact().redundant_rows, d.redundant_rows);
  EXPECT_EQ(artifact().qp().redundant_rows, d.redundant_rows);
  const ParametricQp full = ParametricQp::from_mpc(d);
  std::printf("redundant rows: %zu of %d (state rows %d)\n", d.redundant_rows.size(), full.nc(), d.N * d.n);
  EXPECT_NEAR(static_cast<double>(d.redundant_rows.size()), 86.0, 3.0);  // README
  EXPECT_NEAR(static_cast<double>(artifact().redundant_rows_offset_free.size()), 50.0, 3.0);  // README
  SolverOptions cold;
  cold.warm_start = false;
  auto ref = make_solver("reference", d, cold);
  auto as = make_solver("active-set", d, cold);
  auto warm = make_solver("active-set", d);
  std::vector<Eigen::VectorXd> xs = test::case_study_states(100, 21);
  const std::vector<Eigen::VectorXd> hard = hard_states(full, artifact().x_bar.hi, 30, 22);
  xs.insert(xs.end(), hard.begin(), hard.end());
  double worst_kkt = 0.0, worst_z = 0.0, worst_warm = 0.0, worst_ref_kkt = 0.0;
  int most_active = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    const CondensedQp qp = full.instance(xs[i]);
    const SolveResult r = ref->solve(xs[i]);
    ASSERT_EQ(r.status, SolveStatus::Converged) << "reference, state " << i;
    const SolveResult a = as->solve(xs[i]);
    ASSERT_EQ(a.status, SolveStatus::Converged) << "state " << i;
    const SolveResult w = warm->solve(xs[i]);
    ASSERT_EQ(w.status, SolveStatus::Converged) << "warm, state " << i;
    worst_kkt = std::max({worst_kkt, rel_kkt(qp, a), rel_kkt(qp, w)});
    worst_ref_kkt = std::max(worst_ref_kkt, rel_kkt(qp, r));
    worst_z = std::max(worst_z, (a.z - r.z).cwiseAbs().maxCoeff());
    worst_warm = std::max(worst_warm, (w.z - a.z).cwiseAbs().maxCoeff());
    most_active = std::max(most_active, static_cast<int>((a.y.array() != 0.0).count()));
  }
  std::printf("active-set: KKT %.2e (full QP; the reference %.2e), |z - z_ref| %.2e, warm-cold %.2e, up to %d active rows\n",
              worst_kkt, worst_ref_kkt, worst_z, worst_warm, most_active);
  EXPECT_LT(worst_kkt, 1e-9);
  EXPECT_LT(worst_z, 1e-6);
  EXPECT_LT(worst_warm, 1e-9);
  EXPECT_GE(most_active, 5);  // the hard states exercise the active set
}

TEST(ActiveSet, OffsetFreeAndSoftenedForms) {
  SolverOptions cold;
  cold.warm_start = false;
  const MpcQpData d = certified(artifact().qp(true));
  auto ref = make_solver("reference", d, cold);
  auto as = make_solver("active-set", d, cold);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0, worst_z = 0.0;
  for (const Eigen::VectorXd& x0 : test::case_study_states(60, 9)) {
    Eigen::VectorXd theta(d.parameters());
    Eigen::VectorXd c(24);
    for (int i = 0; i < 24; ++i) c(i) = 1e-5 * u(rng);
    theta << x0, u(rng), u(rng), u(rng), c;
    const SolveResult r = ref->solve(theta);
    ASSERT_EQ(r.status, SolveStatus::Converged);
    const SolveResult a = as->solve(theta);
    ASSERT_EQ(a.status, SolveStatus::Converged);
    worst = std::max(worst, rel_kkt(ParametricQp::from_mpc(d).instance(theta), a));
    worst_z = std::max(worst_z, (a.z - r.z).cwiseAbs().maxCoeff());
  }
  std::printf("offset-free: %zu redundant rows, KKT %.2e, |z - z_ref| %.2e\n", d.redundant_rows.size(), worst, worst_z);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_z, 1e-6);
  // The softened QP, where the hard one is infeasible: the same optimum as the reference.
  MpcQpData s = artifact().qp();
  s.soft_penalty = 50.0;
  auto sref = make_solver("reference", s, cold);
  auto sas = make_solver("active-set", s, cold);
  const ParametricQp soft = ParametricQp::from_mpc(s);
  double worst_soft = 0.0, most_slack = 0.0;
  std::mt19937_64 rng2(31);
  for (int k = 0; k < 30; ++k) {
    Eigen::VectorXd x0(24);
    for (int i = 0; i < 24; ++i) x0(i) = 0.3 * u(rng2) * artifact().x_bar.hi(i);
    const SolveResult r = sref->solve(x0);
    ASSERT_EQ(r.status, SolveStatus::Converged);
    const SolveResult a = sas->solve(x0);
    ASSERT_EQ(a.status, SolveStatus::Converged) << "softened instance " << k << ": " << to_string(a.status);
    worst_soft = std::max(worst_soft, (a.z.head(16) - r.z.head(16)).cwiseAbs().maxCoeff());
    most_slack = std::max(most_slack, a.z.tail(24).maxCoeff());
    EXPECT_LT(rel_kkt(soft.instance(x0), a), 1e-8) << "softened instance " << k;
  }
  std::printf("softened: |u - u_ref| %.2e, largest slack %.3f\n", worst_soft, most_slack);
  EXPECT_LT(worst_soft, 1e-5);
  EXPECT_GT(most_slack, 0.0);  // the hard QPs were infeasible
}

TEST(ActiveSet, InputRateWeightedForm) {
  // The offset-free QP with an input-rate weight (v_prev the parameter's last 4
  // entries): active-set and admm against the reference interior point and the KKT
  // residuals of the full QP; the redundant-row certificate stays valid (it does not
  // depend on the cost). The thesis' ADMM and the constrained-zonotope form refuse it.
  SolverOptions cold;
  cold.warm_start = false;
  MpcQpData d = artifact().qp(true);
  add_input_rate_weight(d, 50.0 * artifact().Sigma_lambda);
  d = certified(d);
  ASSERT_EQ(d.parameters(), 24 + 3 + 24 + 4);
  auto ref = make_solver("reference", d, cold);
  auto as = make_solver("active-set", d, cold);
  auto admm = make_solver("admm", d, cold);
  const ParametricQp p = ParametricQp::from_mpc(d);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0, worst_z = 0.0, worst_admm = 0.0, moved = 0.0;
  for (const Eigen::VectorXd& x0 : test::case_study_states(40, 4)) {
    Eigen::VectorXd theta(d.parameters()), c(24), v(4);
    for (int i = 0; i < 24; ++i) c(i) = 1e-5 * u(rng);
    for (int i = 0; i < 4; ++i) v(i) = 0.5 * u(rng) * d.u_bar.hi(i);
    theta << x0, u(rng), u(rng), u(rng), c, v;
    const SolveResult r = ref->solve(theta);
    ASSERT_EQ(r.status, SolveStatus::Converged);
    const SolveResult a = as->solve(theta);
    ASSERT_EQ(a.status, SolveStatus::Converged);
    const SolveResult b = admm->solve(theta);
    ASSERT_EQ(b.status, SolveStatus::Converged);
    worst = std::max(worst, rel_kkt(p.instance(theta), a));
    worst_z = std::max(worst_z, (a.z - r.z).cwiseAbs().maxCoeff());
    worst_admm = std::max(worst_admm, (b.z - r.z).cwiseAbs().maxCoeff() / (1.0 + r.z.cwiseAbs().maxCoeff()));
    theta.tail(4).setZero();  // the same QP from a steady previous input: another optimum
    moved = std::max(moved, (ref->solve(theta).z - r.z).cwiseAbs().maxCoeff());
  }
  std::printf("rate-weighted: KKT %.2e, |z - z_ref| %.2e, admm %.2e relative, v_prev moves z by %.3f\n", worst, worst_z,
              worst_admm, moved);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_z, 1e-6);
  EXPECT_LT(worst_admm, 1e-2);
  EXPECT_GT(moved, 1e-3);  // the weight acts through v_prev
  EXPECT_THROW(make_solver("admm-thesis", d, cold), std::invalid_argument);
  EXPECT_THROW(make_solver("cz", d, cold), std::invalid_argument);
}

TEST(ActiveSet, CertifiesInfeasibilityWhereTheLpFindsNoPoint) {
  const MpcQpData d = certified(artifact().qp());
  SolverOptions o;
  o.warm_start = false;
  auto as = make_solver("active-set", d, o);
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int infeasible = 0, certified_count = 0, feasible = 0;
  for (int k = 0; k < 60; ++k) {
    Eigen::VectorXd x0(24);  // 3 % to 30 % of the box at once: many without any feasible input
    const double scale = 0.03 + 0.27 * (k % 10) / 9.0;
    for (int i = 0; i < 24; ++i) x0(i) = scale * u(rng) * artifact().x_bar.hi(i);
    const double slack = feasibility_slack(as->problem().instance(x0));
    if (std::abs(slack) < 1e-7) continue;  // CLP's tolerance decides: not scored
    const SolveResult r = as->solve(x0);
    if (slack < 0.0) {
      ++infeasible;
      certified_count += r.status == SolveStatus::Infeasible;
      EXPECT_EQ(r.status, SolveStatus::Infeasible) << "instance " << k;
    } else {
      ++feasible;
      EXPECT_EQ(r.status, SolveStatus::Converged) << "instance " << k;
    }
  }
  std::printf("%d infeasible (LP), %d certified; %d feasible\n", infeasible, certified_count, feasible);
  EXPECT_GT(infeasible, 20);
  EXPECT_GT(feasible, 10);
}

TEST(ActiveSet, OutsideTheCertificatesDomainEveryRowIsKept) {
  MpcQpData d = certified(artifact().qp());
  SolverOptions o;
  o.warm_start = false;
  auto as = make_solver("active-set", d, o);
  d.redundant_rows.clear();
  auto all = make_solver("active-set", d, o);
  // A nominal state just outside X_bar in one coordinate (the domain), small elsewhere.
  Eigen::VectorXd x0 = test::case_study_states(1, 4)[0];
  x0(3) = 1.02 * artifact().x_bar.hi(3);
  ASSERT_FALSE(d.domain.contains(x0));
  ASSERT_TRUE(d.domain.contains(test::case_study_states(1, 4)[0]));
  const SolveResult a = as->solve(x0);
  const SolveResult b = all->solve(x0);
  ASSERT_EQ(a.status, b.status);
  if (a.status == SolveStatus::Converged) {
    EXPECT_LT((a.z - b.z).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT(rel_kkt(as->problem().instance(x0), a), 1e-9);
  }
}

}  // namespace
}  // namespace tmpc
