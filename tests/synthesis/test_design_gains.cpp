// The design paths every other fixture turns off: the default configuration as
// shipped (compare_gains: true, the two LMI forms solved next to LQR), and the LMIs at
// all 8 LPV vertices (lmi.vertices: true, about two minutes of CSDP here). The LMI
// (3.21) is rebuilt here from the returned W and K at every model and checked by its
// eigenvalues, independently of the gain code's own checks.
#include <cstdio>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "design_fixture.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {
namespace {

/// Smallest eigenvalue of (3.21) at vertex A: [W, (CW+DY)', (AW+BY)'; CW+DY, I, 0;
/// AW+BY, 0, W] with C = [Q^1/2; 0], D = [0; R^1/2] (C'C = Q, D'D = R, C'D = 0), Y = K W.
double riccati_lmi_min_eigenvalue(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                                  const Eigen::MatrixXd& R, const Eigen::MatrixXd& W, const Eigen::MatrixXd& K) {
  const Eigen::Index n = A.rows(), m = B.cols();
  const Eigen::MatrixXd Qh = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Q).operatorSqrt();
  const Eigen::MatrixXd Rh = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(R).operatorSqrt();
  const Eigen::MatrixXd Y = K * W;
  Eigen::MatrixXd CWDY(n + m, n);
  CWDY << Qh * W, Rh * Y;
  const Eigen::MatrixXd AWBY = A * W + B * Y;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * n + m, 3 * n + m);
  M.topLeftCorner(n, n) = W;
  M.block(n, 0, n + m, n) = CWDY;
  M.block(0, n, n, n + m) = CWDY.transpose();
  M.block(n, n, n + m, n + m).setIdentity();
  M.block(2 * n + m, 0, n, n) = AWBY;
  M.block(0, 2 * n + m, n, n) = AWBY.transpose();
  M.bottomRightCorner(n, n) = W;
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (M + M.transpose())).eigenvalues().minCoeff();
}

const GainDesign* gain(const ControllerDesign& d, const std::string& name) {
  for (const GainDesign& g : d.gains) {
    if (g.name == name) return &g;
  }
  return nullptr;
}

// README: the report compares the gains by their tubes; the default (LQR) has the
// largest robustness margin (15.31 against 10.76 and 12.68 for the LMI forms over the
// shipped envelope).
TEST(DesignGains, TheShippedConfigurationComparesTheThreeGains) {
  const Config cfg = test::default_config();
  ASSERT_TRUE(cfg.synthesis.compare_gains);
  ASSERT_EQ(cfg.synthesis.tube_gain, "lqr");
  const ControllerDesign d = design_controller(cfg, test::default_config_text());
  const GainDesign* lqr = gain(d, "lqr");
  const GainDesign* thesis = gain(d, "lmi_thesis");
  const GainDesign* robust = gain(d, "lmi_robust");
  ASSERT_TRUE(lqr && thesis && robust);
  for (const GainDesign* g : {lqr, thesis, robust}) {
    EXPECT_TRUE(g->available) << g->name << ": " << g->message;
    EXPECT_TRUE(g->tube_ok) << g->name << ": " << g->tube_message;
    ASSERT_EQ(g->vertex_spectral_radius.size(), 9u);
    for (double r : g->vertex_spectral_radius) EXPECT_LT(r, 1.0) << g->name;
  }
  std::printf("margins: lqr %.3f, lmi_thesis %.3f, lmi_robust %.3f\n", lqr->margin, thesis->margin, robust->margin);
  EXPECT_NEAR(lqr->margin, 15.31, 0.1);  // the servo torques' LQR weights x 100 (17.27 with lambda's)
  EXPECT_NEAR(thesis->margin, 10.76, 0.1);
  EXPECT_NEAR(robust->margin, 12.68, 0.1);
  EXPECT_EQ(d.gains[static_cast<std::size_t>(d.selected)].name, "lqr");
  EXPECT_GT(lqr->margin, std::max(thesis->margin, robust->margin));
  // The thesis form's gain satisfies (3.21) at the nominal model (its only model here),
  // to the SDP solver's tolerance (about 1e-7 relative; 1e-6 of ||W|| allowed).
  const double e = riccati_lmi_min_eigenvalue(d.em.A_n, d.em.B_n, d.Sigma_rho_n, d.Sigma_lambda_n, thesis->lmi.W,
                                              thesis->lmi.K);
  std::printf("(3.21) at the nominal model: min eigenvalue %.3e (||W|| %.3e)\n", e, thesis->lmi.W.norm());
  EXPECT_GT(e, -1e-6 * std::max(1.0, thesis->lmi.W.norm()));
  // The artifact is the LQR design, the same as the quick fixture's.
  EXPECT_EQ(make_artifact(d).K, test::quick_artifact().K);
}

TEST(DesignGains, TheLmisAtEveryLpvVertex) {
  Config cfg = test::quick_config();
  cfg.synthesis.lmi_vertices = true;
  cfg.synthesis.tube_gain = "lmi_thesis";
  const ControllerDesign d = design_controller(cfg, test::default_config_text());
  const GainDesign* g = gain(d, "lmi_thesis");
  ASSERT_TRUE(g && g->available) << (g ? g->message : "no gain");
  ASSERT_EQ(d.vertices.size(), 9u);
  double worst = 1e300, worst_radius = 0.0;
  for (const Eigen::MatrixXd& A : d.vertices) {
    worst = std::min(worst, riccati_lmi_min_eigenvalue(A, d.em.B_n, d.Sigma_rho_n, d.Sigma_lambda_n, g->lmi.W, g->lmi.K));
    worst_radius = std::max(worst_radius, spectral_radius(A + d.em.B_n * g->lmi.K));
  }
  std::printf("lmi.vertices: true: (3.21) min eigenvalue over the 9 models %.3e, worst spectral radius %.6f, margin %.3f\n",
              worst, worst_radius, d.margin);
  EXPECT_GT(worst, -1e-6 * std::max(1.0, g->lmi.W.norm()));  // the SDP solver's tolerance
  EXPECT_LT(worst_radius, 1.0);
  EXPECT_EQ(d.gains[static_cast<std::size_t>(d.selected)].name, "lmi_thesis");
  EXPECT_GT(d.margin, 1.0);
  // Solved at all 9 models, the gain differs from the nominal-only one.
  EXPECT_GT(g->lmi.block_names.size(), 9u);
}

}  // namespace
}  // namespace tmpc
