// Linear error model: the equivalence-principle structure at hover, exact affinity
// in sigma, the integrals, ZOH against an independent integration, normalization.
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "tmpc/model/error_model.hpp"
#include "tmpc/model/reference.hpp"

namespace tmpc {
namespace {

const ErrorModel& default_error_model() {
  static const ErrorModel em = build_error_model(test::default_config());
  return em;
}

TEST(ErrorModel, EquivalencePrincipleStructureAtHover) {
  // Model spec 5: at phi = theta = psi = 0, K[:, theta] = -g M[:, x] and
  // K[:, phi] = g M[:, y], so A_c[x'', theta] = +g and A_c[y'', phi] = -g with the
  // rest of those columns zero.
  const ErrorModel& em = default_error_model();
  const double g = test::default_config().vehicle.gravity;
  const auto& A = em.lpv.A0;
  Eigen::Matrix<double, kNx, 1> e_theta = Eigen::Matrix<double, kNx, 1>::Zero(), e_phi = e_theta;
  e_theta(kNq + kX) = g;
  e_phi(kNq + kY) = -g;
  EXPECT_LT((A.col(kTheta) - e_theta).norm(), 1e-9);
  EXPECT_LT((A.col(kPhi) - e_phi).norm(), 1e-9);
  // Kinematic block [0 I].
  EXPECT_LT((A.topLeftCorner<kNq, kNq>().norm()), 1e-14);
  EXPECT_LT(((A.topRightCorner<kNq, kNq>() - Mat10::Identity()).norm()), 1e-14);
  // Position is cyclic: no force depends on x, y, z.
  EXPECT_LT(A.leftCols<3>().norm(), 1e-12);
}

TEST(ErrorModel, LpvIsExactlyAffineInSigmaForTheThesisLiteralAttitude) {
  Config cfg = test::default_config();
  cfg.attitude = ReferenceAttitude::Equilibrium;
  const TiltrotorModel model(cfg.vehicle);
  const ErrorModel em = build_error_model(cfg);
  // Independent evaluation: linearize at u_r(sigma) for a sigma off the unit vectors.
  const Eigen::Vector3d sigma(0.03, -0.02, 0.015);
  ReferencePoint r;
  r.q = em.equilibrium.q();
  r.qdd.head<3>() = sigma;
  State20 x;
  x << r.q, Vec10::Zero();
  const Mat20 A = model.linearize(x, feedforward(model, r), Eigen::Vector3d::Zero()).A;
  EXPECT_LT((A - em.lpv.at(sigma)).norm(), 1e-9 * A.norm());
  EXPECT_EQ(em.A_vertices.size(), 8u);
  // The sigma box is the configured envelope, its vertices its 8 corners.
  EXPECT_EQ(em.lpv.sigma_min, cfg.envelope.acceleration_min);
  EXPECT_EQ(em.lpv.sigma_max, cfg.envelope.acceleration_max);
  for (const Eigen::Vector3d& v : em.lpv.vertex_sigma) {
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(v(i) == em.lpv.sigma_min(i) || v(i) == em.lpv.sigma_max(i));
  }
  // At a fixed attitude, A is affine in sigma up to rounding.
  EXPECT_LT(em.lpv.affinity_residual, 1e-9);
  EXPECT_LT(em.lpv.b_variation, 1e-12);  // B does not depend on sigma here
}

TEST(ErrorModel, TrimAttitudeIsNearlyAffineAndReportsIt) {
  const Config& cfg = test::default_config();
  const TiltrotorModel model(cfg.vehicle);
  const ErrorModel& em = default_error_model();
  EXPECT_EQ(em.A_vertices.size(), 8u);
  // The true A over the envelope stays close to the LPV fit, B nearly constant (README:
  // 3.8e-5 of ||A0|| and 4.2e-4 over the shipped envelope).
  EXPECT_NEAR(em.lpv.affinity_residual, 3.76e-5, 0.1 * 3.76e-5);
  EXPECT_NEAR(em.lpv.b_variation, 4.24e-4, 0.1 * 4.24e-4);
  // A at a vertex from the model itself is within the reported residual of the fit.
  const Eigen::Vector3d s = em.lpv.vertex_sigma[5];
  const Trim t = solve_trim(model, s, Eigen::Vector3d::Zero(), 0.0, em.equilibrium);
  State20 x = State20::Zero();
  x.segment<2>(kPhi) = t.attitude;
  x.segment<4>(kGamma1) = t.angles;
  const Mat20 A = model.linearize(x, t.u, Eigen::Vector3d::Zero()).A;
  EXPECT_LT((A - em.lpv.at(s)).norm() / em.lpv.A0.norm(), std::max(1e-9, 2.0 * em.lpv.affinity_residual));
}

TEST(ErrorModel, IntegralsOfXYZPsi) {
  const ErrorModel& em = default_error_model();
  const int integrated[4] = {kX, kY, kZ, kPsi};
  for (int i = 0; i < 4; ++i) {
    Eigen::Matrix<double, 1, kNa> row = Eigen::Matrix<double, 1, kNa>::Zero();
    row(integrated[i]) = 1.0;
    EXPECT_EQ(em.A_c.row(kNx + i), row);
    EXPECT_EQ(em.B_c.row(kNx + i).norm(), 0.0);
  }
}

TEST(ErrorModel, ZeroOrderHoldMatchesAnIndependentIntegration) {
  // Integrate x' = A_c x + B_c u over one period with RK4 at T/2000 from x0, u held.
  const ErrorModel& em = default_error_model();
  using Vec24 = Eigen::Matrix<double, kNa, 1>;
  Vec24 x0 = Vec24::Random();
  const Eigen::Vector4d u = Eigen::Vector4d::Random();
  const int n = 2000;
  const double h = em.sample_time / n;
  Vec24 x = x0;
  auto f = [&](const Vec24& s) -> Vec24 { return em.A_c * s + em.B_c * u; };
  for (int i = 0; i < n; ++i) {
    const Vec24 k1 = f(x), k2 = f(x + 0.5 * h * k1), k3 = f(x + 0.5 * h * k2), k4 = f(x + h * k3);
    x += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  const Vec24 zoh = em.A * x0 + em.B * u;
  EXPECT_LT((zoh - x).norm(), 1e-10 * (1.0 + x.norm()));
}

TEST(ErrorModel, EulerOptionIsIPlusAT) {
  Config cfg = test::default_config();
  cfg.error_model.discretization = Discretization::Euler;
  const ErrorModel em = build_error_model(cfg);
  EXPECT_LT((em.A - (Eigen::MatrixXd::Identity(kNa, kNa) + em.A_c * cfg.sample_time)).norm(), 1e-14);
  EXPECT_LT((em.B - em.B_c * cfg.sample_time).norm(), 1e-14);
}

TEST(ErrorModel, NormalizationMapsTheBoxesToUnitBoxes) {
  const Config& cfg = test::default_config();
  const ErrorModel& em = default_error_model();
  EXPECT_LT((em.N_x.cwiseProduct(cfg.state_error_max) - Eigen::VectorXd::Ones(kNa)).norm(), 1e-14);
  EXPECT_LT((em.N_u.cwiseProduct(0.5 * (cfg.input_max - cfg.input_min)) - Eigen::Vector4d::Ones()).norm(), 1e-14);
  // The normalized model propagates normalized states: N_x (A x + B u) = A_n N_x x + B_n N_u u.
  const Eigen::VectorXd x = Eigen::VectorXd::Random(kNa);
  const Eigen::Vector4d u = Eigen::Vector4d::Random();
  const Eigen::VectorXd lhs = em.N_x.asDiagonal() * (em.A * x + em.B * u);
  const Eigen::VectorXd rhs = em.A_n * em.N_x.cwiseProduct(x) + em.B_n * em.N_u.cwiseProduct(u);
  EXPECT_LT((lhs - rhs).norm(), 1e-12 * lhs.norm());
}

TEST(ErrorModel, InputErrorBoxHoldsAlongTheMission) {
  const Config& cfg = test::default_config();
  const ErrorModel& em = default_error_model();
  // Thrusts around 11.7 N in [0, 30]: the error box is [0 - max u_r, 30 - min u_r], so
  // that u_r + u_tilde stays inside the limits for every feedforward of the envelope.
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT(em.input_error_min(i), 0.0);
    EXPECT_GT(em.input_error_max(i), 0.0);
    EXPECT_LE(em.u_r_min(i), em.u_r_max(i));
  }
  EXPECT_NEAR(em.input_error_min(0), cfg.input_min(0) - em.u_r_max(0), 1e-15);
  EXPECT_NEAR(em.input_error_max(0), cfg.input_max(0) - em.u_r_min(0), 1e-15);
  // The range covers the feedforward of a trajectory inside the envelope, sampled
  // independently: the helix's u_r at a few times.
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator gen(model, test::thesis_helix());
  for (double t : {0.0, 11.0, 23.5, 47.0, 71.0}) {
    const Eigen::Vector4d u = feedforward(model, gen.at(t));
    for (int i = 0; i < 4; ++i) {
      EXPECT_GE(u(i), em.u_r_min(i) - 1e-9) << "t = " << t;
      EXPECT_LE(u(i), em.u_r_max(i) + 1e-9) << "t = " << t;
    }
  }
}

/// The error building the model from `cfg` reports ("" when it builds).
std::string design_error(const Config& cfg) {
  try {
    build_error_model(cfg);
  } catch (const ConfigError& err) {
    return err.what();
  }
  return "";
}

TEST(ErrorModel, EnvelopeFromTrajectoriesAndTrajectoriesOutsideTheBox) {
  // Without a box, the envelope is the named trajectories' range widened by the margin.
  Config cfg = test::default_config();
  cfg.envelope.acceleration_min.setZero();
  cfg.envelope.acceleration_max.setZero();
  cfg.envelope.speed_max = 0.0;
  cfg.envelope.trajectories = {"scenarios/thesis_helix.yaml"};
  const EnvelopeSettings e = resolve_envelope(cfg);
  const double w2 = (M_PI / 40) * (M_PI / 40);
  EXPECT_NEAR(e.acceleration_max.x(), 1.1 * 5.0 * w2, 1e-3 * 5.0 * w2);  // the helix: r w^2, +10 %
  EXPECT_NEAR(e.acceleration_min.z(), -1.1 * 3.0 * w2, 1e-3 * 3.0 * w2);
  EXPECT_GT(e.speed_max, 0.4);
  // A configured box that a named trajectory leaves is an error naming both.
  cfg = test::default_config();
  cfg.envelope.acceleration_max.x() = 0.05;  // the figure-eight reaches 0.058 m/s^2 along x
  std::string msg = design_error(cfg);
  EXPECT_NE(msg.find("envelope.acceleration_min/max"), std::string::npos) << msg;
  EXPECT_NE(msg.find("figure_eight.yaml"), std::string::npos) << msg;
  // A named trajectory that turns faster than the any-yaw bound (the helix flown nose
  // first turns at pi / 40 = 0.0785 rad/s).
  cfg = test::default_config();
  ASSERT_TRUE(cfg.envelope.any_yaw());
  cfg.envelope.yaw_rate_max = 0.05;
  msg = design_error(cfg);
  EXPECT_NE(msg.find("envelope.yaw_rate_max"), std::string::npos) << msg;
  EXPECT_NE(msg.find("helix_nose_first.yaml turns at 0.078"), std::string::npos) << msg;
}

}  // namespace
}  // namespace tmpc
