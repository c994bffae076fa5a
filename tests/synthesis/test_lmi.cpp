// The SDP layer and Theorem 3.1. Every LMI solution is checked here by building
// the inequalities again from K and W with plain matrices (not CSDP's word).
#include <random>

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "design_fixture.hpp"
#include "tmpc/synthesis/lmi_gain.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {
namespace {

double min_eig(const Eigen::MatrixXd& m) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (m + m.transpose())).eigenvalues().minCoeff();
}

TEST(Sdp, SolvesASmallProblemAndReportsInfeasibility) {
  // min t s.t. [t 1; 1 t] >= 0  ->  t = 1.
  LmiProblem p;
  const int t = p.add_scalar();
  AffineMatrix f(2, 2);
  f.add_term(t, 0, 0, 1.0);
  f.add_term(t, 1, 1, 1.0);
  f = f + AffineMatrix::constant((Eigen::MatrixXd(2, 2) << 0, 1, 1, 0).finished());
  p.require_psd(f, "[t 1; 1 t]");
  p.set_objective(t, 1.0);
  const SdpResult r = p.solve();
  ASSERT_TRUE(r.usable()) << r.message;
  EXPECT_NEAR(r.y(t), 1.0, 1e-6);
  EXPECT_GT(p.block_min_eigenvalues(r.y)[0], -1e-7);
  // t >= 1 and -t >= 0 together: infeasible, with the solver's message.
  LmiProblem q;
  const int s = q.add_scalar();
  q.require_psd(q.scalar_expr(s) - AffineMatrix::constant(Eigen::MatrixXd::Ones(1, 1)), "s >= 1");
  q.require_psd(q.scalar_expr(s) * -1.0, "s <= 0");
  q.set_objective(s, 1.0);
  const SdpResult bad = q.solve();
  EXPECT_EQ(bad.status, SdpStatus::Infeasible) << to_string(bad.status) << ": " << bad.message;
  EXPECT_FALSE(bad.message.empty());
}

/// Theorem 3.1's inequalities rebuilt from K and W.
void expect_lmis_hold(const LmiGainProblem& p, const LmiGainResult& r) {
  const Eigen::Index n = p.B.rows(), m = p.B.cols(), q = p.Hw.cols();
  const Eigen::MatrixXd& W = r.W;
  const Eigen::MatrixXd Y = r.K * W;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(p.Q);
  const Eigen::MatrixXd Qh = es.eigenvectors() * es.eigenvalues().cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
  const Eigen::MatrixXd Rh = p.R.diagonal().cwiseSqrt().asDiagonal();
  const double tol = -1e-6 * std::max(1.0, W.norm());
  EXPECT_GT(min_eig(W), 0.0);
  for (const Eigen::MatrixXd& A : p.A) {
    const Eigen::MatrixXd X = A * W + p.B * Y;
    Eigen::MatrixXd CW(n + m, n);
    CW << Qh * W, Rh * Y;
    Eigen::MatrixXd ric = Eigen::MatrixXd::Zero(3 * n + m, 3 * n + m);
    ric.block(0, 0, n, n) = W;
    ric.block(n, 0, n + m, n) = CW;
    ric.block(0, n, n, n + m) = CW.transpose();
    ric.block(n, n, n + m, n + m).setIdentity();
    ric.block(2 * n + m, 0, n, n) = X;
    ric.block(0, 2 * n + m, n, n) = X.transpose();
    ric.block(2 * n + m, 2 * n + m, n, n) = W;
    EXPECT_GT(min_eig(ric), tol) << "Riccati LMI (3.21)";
    const Eigen::Index k = p.form == LmiForm::Thesis ? 1 : q;
    Eigen::MatrixXd inv = Eigen::MatrixXd::Zero(2 * n + k, 2 * n + k);
    inv.block(0, 0, n, n) = p.lambda * W;
    inv.block(n + k, 0, n, n) = X;
    inv.block(0, n + k, n, n) = X.transpose();
    inv.block(n + k, n + k, n, n) = W;
    if (p.form == LmiForm::Thesis) {
      inv(n, n) = 1.0 - p.lambda;
      inv.block(n + 1, n, n, 1) = p.Hw * r.zeta;
      inv.block(n, n + 1, 1, n) = (p.Hw * r.zeta).transpose();
      EXPECT_LE(r.zeta.norm(), 1.0 + 1e-6);
    } else {
      inv.block(n, n, q, q) = ((1.0 - p.lambda) / static_cast<double>(q)) * Eigen::MatrixXd::Identity(q, q);
      inv.block(n + q, n, n, q) = p.Hw;
      inv.block(n, n + q, q, n) = p.Hw.transpose();
    }
    EXPECT_GT(min_eig(inv), tol) << "invariance LMI";
    EXPECT_LT((A + p.B * r.K).eigenvalues().cwiseAbs().maxCoeff(), 1.0);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    EXPECT_LE(r.K.row(j) * W * r.K.row(j).transpose(), p.u_max(j) * p.u_max(j) * (1.0 + 1e-6)) << "input bound (3.19)";
  }
}

TEST(LmiGain, BothFormsOnRandomStabilizableSystemsSatisfyTheirInequalities) {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  int solved = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const int n = 3, m = 1;
    Eigen::MatrixXd A0(n, n), B(n, m);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) A0(i, j) = 0.4 * g(rng);
      B(i, 0) = g(rng);
    }
    A0 += 0.8 * Eigen::MatrixXd::Identity(n, n);
    LmiGainProblem p;
    p.A = {A0, A0 + 0.02 * Eigen::MatrixXd::Random(n, n), A0 + 0.02 * Eigen::MatrixXd::Random(n, n)};
    p.B = B;
    p.Q = Eigen::MatrixXd::Identity(n, n);
    p.R = Eigen::MatrixXd::Identity(m, m);
    p.Hw = 1e-3 * Eigen::MatrixXd::Identity(n, n);
    p.u_max = Eigen::VectorXd::Constant(m, 10.0);
    p.lambda = 0.95;
    p.w_floor = 1e-6;
    for (LmiForm form : {LmiForm::Thesis, LmiForm::Robust}) {
      p.form = form;
      const LmiGainResult r = solve_lmi_gain(p);
      if (!r.feasible) continue;  // some random systems are not stabilizable at this rate
      ++solved;
      expect_lmis_hold(p, r);
    }
  }
  EXPECT_GE(solved, 6);
}

TEST(LmiGain, CaseStudyThesisFormAtTheNominalModel) {
  const ControllerDesign& d = test::quick_design();
  LmiGainProblem p;
  p.A = {d.em.A_n};
  p.B = d.em.B_n;
  p.Q = d.Sigma_rho_n;
  p.R = d.Sigma_lambda_n;
  p.Hw = d.W.G;
  p.u_max = d.U.lo.cwiseAbs().cwiseMin(d.U.hi);
  p.lambda = 0.99;
  p.w_floor = 1e-4;
  p.form = LmiForm::Thesis;
  const LmiGainResult r = solve_lmi_gain(p);
  ASSERT_TRUE(r.feasible) << r.message;
  expect_lmis_hold(p, r);
  // E4: zeta = 0 is admissible, the solver returns (nearly) zero: W drops out.
  EXPECT_LT((d.W.G * r.zeta).norm(), 1e-6);
  // Every LPV vertex is stabilized too (checked, though the LMIs used the nominal model).
  for (const Eigen::MatrixXd& A : d.vertices) EXPECT_LT(spectral_radius(A + d.em.B_n * r.K), 1.0);
}

TEST(Lqr, DareResidualAndStabilityOnTheCaseStudyAndRandomSystems) {
  const ControllerDesign& d = test::quick_design();
  const Eigen::MatrixXd& A = d.em.A_n;
  const Eigen::MatrixXd& B = d.em.B_n;
  const LqrResult r = solve_dlqr(A, B, d.Sigma_rho_n, d.Sigma_lambda_n);
  const Eigen::MatrixXd S = d.Sigma_lambda_n + B.transpose() * r.P * B;
  const Eigen::MatrixXd res = A.transpose() * r.P * A - r.P + d.Sigma_rho_n -
                              A.transpose() * r.P * B * S.inverse() * B.transpose() * r.P * A;
  EXPECT_LT(res.norm() / r.P.norm(), 1e-9);
  EXPECT_NEAR(r.spectral_radius, 0.994001, 1e-5);  // research/tube_feasibility.md: 0.9940
  // The gain is the minimizer: K = -(R + B'PB)^-1 B'PA.
  EXPECT_LT((r.K + S.inverse() * B.transpose() * r.P * A).norm(), 1e-9 * r.K.norm());
  EXPECT_THROW(solve_dlqr(Eigen::MatrixXd::Identity(2, 2) * 1.1, Eigen::MatrixXd::Zero(2, 1),
                          Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Identity(1, 1)),
               std::runtime_error);
}

}  // namespace
}  // namespace tmpc
