// Euler-Lagrange terms: structure (M SPD, M-dot - 2C skew), two independent
// Coriolis formulas, the model spec's validation values, and the AD Jacobians of f
// against central finite differences.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "test_support.hpp"

namespace tmpc {
namespace {

Vec10 thesis_equilibrium_q() {
  Vec10 q = Vec10::Zero();
  q.segment<4>(kGamma1) << 1.316967e-4, 0.0139602, 0.0140053, 0.0138091;
  return q;
}

TEST(Dynamics, MassMatrixIsSymmetricPositiveDefiniteAt1000States) {
  const TiltrotorModel model(test::default_config().vehicle);
  std::mt19937_64 rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Mat10 M = model.mass_matrix(test::random_q(rng));
    ASSERT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-12 * M.cwiseAbs().maxCoeff());
    Eigen::SelfAdjointEigenSolver<Mat10> es(M);
    ASSERT_GT(es.eigenvalues().minCoeff(), 0.0);
  }
}

TEST(Dynamics, MdotMinus2CIsSkewWithMdotByFiniteDifferences) {
  const TiltrotorModel model(test::default_config().vehicle);
  std::mt19937_64 rng(2);
  const double h = 1e-6;
  for (int i = 0; i < 200; ++i) {
    const Vec10 q = test::random_q(rng), qd = test::random_qd(rng);
    const Mat10 Mdot = (model.mass_matrix(q + h * qd) - model.mass_matrix(q - h * qd)) / (2 * h);
    const Mat10 N = Mdot - 2.0 * model.coriolis_matrix(q, qd);
    EXPECT_LT((N + N.transpose()).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + Mdot.cwiseAbs().maxCoeff()));
  }
}

TEST(Dynamics, NewtonEulerCoriolisEqualsChristoffelForm) {
  // c from body accelerations (J-dot q') against C(q, q') q' from derivatives of M.
  const TiltrotorModel model(test::default_config().vehicle);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200; ++i) {
    const Vec10 q = test::random_q(rng), qd = test::random_qd(rng);
    const Vec10 c1 = model.coriolis_vector(q, qd);
    const Vec10 c2 = model.coriolis_matrix(q, qd) * qd;
    EXPECT_LT((c1 - c2).norm(), 1e-12 * (1.0 + c1.norm()));
  }
}

TEST(Dynamics, ModelSpecValidationValuesAtTheEquilibrium) {
  // shared/research/tiltrotor_model.md section 6, set S1.
  const TiltrotorModel model(test::default_config().vehicle);
  const Vec10 q = thesis_equilibrium_q();
  const Vec10 diag = model.mass_matrix(q).diagonal();
  const double diag_ref[10] = {2.38636, 2.38636, 2.38636, 0.67518, 0.65874, 0.01884, 0.03699, 0.02056, 0.00065, 0.00065};
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(diag(i), diag_ref[i], 0.5e-5 + 5e-3 * diag_ref[i]) << "M(" << i << "," << i << ")";
  const Vec10 G = model.gravity_vector(q);
  const double G_ref[10] = {0, 0, 23.41019, 0.01036, 0.09373, 0, -0.01036, -0.09373, 0, 1e-5};
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(G(i), G_ref[i], 1e-5) << "G(" << i << ")";
  const Vec10 L0 = model.input_matrix(q).col(0);
  const double L_ref[10] = {1e-4, 0.08728, 0.99618, -0.33546, 0.00406, 0.01778, 0.29182, -0.00401, 0, 0};
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(L0(i), L_ref[i], 1e-5) << "L_in(" << i << ",0)";
  // Inverse mass matrix entries quoted for S1 (spec 6): 0.428, 746, 3707.
  const Mat10 Minv = model.mass_matrix(q).inverse();
  EXPECT_NEAR(Minv(kZ, kZ), 0.428, 1e-3);
  EXPECT_NEAR(Minv(kGamma2, kGamma2), 746.0, 1.0);
  EXPECT_NEAR(Minv(kAlphaR, kAlphaR), 3707.0, 2.0);
}

TEST(Dynamics, ParameterSetS2ShiftsTheRotorInertiaToThePivot) {
  Config cfg = test::default_config();
  cfg.vehicle.rotor_inertia_reference = RotorInertiaReference::Pivot;
  const Eigen::Matrix3d Ic = cfg.vehicle.rotor_inertia_about_com();
  EXPECT_NEAR(Ic(0, 0), 1.79e-5, 0.01e-5);  // spec 7.1: diag(1.79e-5, 1.79e-5, 6.4159e-4)
  EXPECT_NEAR(Ic(2, 2), 6.4159e-4, 1e-8);
  const TiltrotorModel s1(test::default_config().vehicle), s2(cfg.vehicle);
  const Vec10 q = thesis_equilibrium_q();
  // The tilt axis is the rotor y axis through the pivot: its diagonal entry of M is
  // the pivot inertia I_yy, i.e. the config value for S2 and I_yy + m c_z^2 for S1.
  const VehicleParams& p = cfg.vehicle;
  const double cz = p.rotor_com.z();
  EXPECT_NEAR(s2.mass_matrix(q)(kAlphaR, kAlphaR), p.rotor_inertia(1, 1), 1e-12);
  EXPECT_NEAR(s1.mass_matrix(q)(kAlphaR, kAlphaR), p.rotor_inertia(1, 1) + p.rotor_mass * cz * cz, 1e-12);
}

TEST(Dynamics, JacobiansOfFMatchCentralFiniteDifferences) {
  const TiltrotorModel model(test::default_config().vehicle);
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    State20 x;
    x << test::random_q(rng), test::random_qd(rng);
    const Eigen::Vector4d u = test::random_u(rng);
    const Eigen::Vector3d d = Eigen::Vector3d::Random();
    const Linearization lin = model.linearize(x, u, d);
    Eigen::Matrix<double, kNx, kNx + kNu + kNd> ad, fd;
    ad << lin.A, lin.B, lin.D;
    for (int j = 0; j < kNx + kNu + kNd; ++j) {
      // Step relative to the variable's scale; central differences.
      State20 xp = x, xm = x;
      Eigen::Vector4d up = u, um = u;
      Eigen::Vector3d dp = d, dm = d;
      double h;
      if (j < kNx) {
        h = 1e-6 * std::max(1.0, std::abs(x(j)));
        xp(j) += h;
        xm(j) -= h;
      } else if (j < kNx + kNu) {
        h = 1e-6 * std::max(1.0, std::abs(u(j - kNx)));
        up(j - kNx) += h;
        um(j - kNx) -= h;
      } else {
        h = 1e-6;
        dp(j - kNx - kNu) += h;
        dm(j - kNx - kNu) -= h;
      }
      fd.col(j) = (model.state_derivative(xp, up, dp) - model.state_derivative(xm, um, dm)) / (2 * h);
    }
    const double rel = (ad - fd).norm() / ad.norm();
    EXPECT_LT(rel, 1e-6) << "trial " << trial;
  }
}

}  // namespace
}  // namespace tmpc
