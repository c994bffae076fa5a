// Our coordinates <-> MuJoCo's: round trip at random states (attitudes away from
// zero) and the Euler-acceleration mapping against finite differences of E(eta).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "../model/test_support.hpp"
#include "tmpc/sim/mujoco_state_map.hpp"

namespace tmpc {
namespace {

State20 random_state(std::mt19937_64& rng) {
  State20 x;
  x << test::random_q(rng), test::random_qd(rng);
  std::uniform_real_distribution<double> att(-1.2, 1.2);
  x(kPhi) = att(rng);
  x(kTheta) = att(rng);  // well inside (-pi/2, pi/2)
  return x;
}

TEST(MujocoStateMap, RoundTripIsExactAtRandomStates) {
  std::mt19937_64 rng(21);
  for (int i = 0; i < 1000; ++i) {
    const State20 x = random_state(rng);
    mujoco_map::Qpos qpos;
    mujoco_map::Qvel qvel;
    mujoco_map::to_mujoco(x, qpos, qvel);
    EXPECT_NEAR(qpos.segment<4>(3).norm(), 1.0, 1e-15);
    const State20 y = mujoco_map::from_mujoco(qpos, qvel, x(kPsi));
    ASSERT_LT((x - y).cwiseAbs().maxCoeff(), 1e-12) << "state " << i;
  }
}

TEST(MujocoStateMap, QuaternionIsTheZyxRotationAndRatesAreBodyRates) {
  // Independent oracle: rotation matrices from elementary rotations and the body
  // angular velocity from a finite difference of R.
  std::mt19937_64 rng(22);
  auto R_of = [](const State20& s) {
    return Eigen::Matrix3d(Eigen::AngleAxisd(s(kPsi), Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(s(kTheta), Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(s(kPhi), Eigen::Vector3d::UnitX()));
  };
  for (int i = 0; i < 100; ++i) {
    const State20 x = random_state(rng);
    mujoco_map::Qpos qpos;
    mujoco_map::Qvel qvel;
    mujoco_map::to_mujoco(x, qpos, qvel);
    const Eigen::Quaterniond q(qpos(3), qpos(4), qpos(5), qpos(6));
    EXPECT_LT((q.toRotationMatrix() - R_of(x)).norm(), 1e-14);
    const double h = 1e-6;
    State20 xp = x, xm = x;
    xp.segment<3>(kPhi) += h * x.segment<3>(kNq + kPhi);
    xm.segment<3>(kPhi) -= h * x.segment<3>(kNq + kPhi);
    const Eigen::Matrix3d W = R_of(x).transpose() * (R_of(xp) - R_of(xm)) / (2 * h);
    EXPECT_LT((Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0)) - qvel.segment<3>(3)).norm(), 1e-8);
  }
}

TEST(MujocoStateMap, EulerAccelerationMappingInvertsTheBodyRateDerivative) {
  std::mt19937_64 rng(23);
  for (int i = 0; i < 100; ++i) {
    const State20 x = random_state(rng);
    const Eigen::Vector3d eta = x.segment<3>(kPhi), etad = x.segment<3>(kNq + kPhi);
    const Eigen::Vector3d etadd = Eigen::Vector3d::Random();
    // w = E(eta) eta': w' by a central difference along the motion.
    const double h = 1e-6;
    auto w_at = [&](double s) {
      const Eigen::Vector3d e = eta + s * etad + 0.5 * s * s * etadd;
      const Eigen::Vector3d ed = etad + s * etadd;
      return Eigen::Vector3d(mujoco_map::euler_rate_matrix(e(0), e(1)) * ed);
    };
    const Eigen::Vector3d wdot = (w_at(h) - w_at(-h)) / (2 * h);
    mujoco_map::Qvel qacc = mujoco_map::Qvel::Random();
    qacc.segment<3>(3) = wdot;
    const Vec10 qdd = mujoco_map::acceleration_from_mujoco(x, qacc);
    EXPECT_LT((qdd.segment<3>(kPhi) - etadd).norm(), 1e-7);
    EXPECT_EQ(qdd.head<3>(), qacc.head<3>());
  }
}

}  // namespace
}  // namespace tmpc
