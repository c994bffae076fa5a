// Kinematic tree: frames against the model spec's closed-form rotations, and the
// geometric Jacobians against finite differences of the positions.
#include <gtest/gtest.h>

#include "test_support.hpp"
#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {
namespace {

Eigen::Matrix3d Rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d Ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d Rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

TEST(KinematicTree, FramesMatchTheModelSpecFormulas) {
  const Config& cfg = test::default_config();
  const VehicleParams& p = cfg.vehicle;
  const KinematicTree tree(p);
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec10 q = test::random_q(rng);
    const TreePose<double> pose = tree.pose(q.data());
    // Spec section 1, typed independently of the tree.
    const Eigen::Matrix3d R_IL = Rz(q(kPsi)) * Ry(q(kTheta)) * Rx(q(kPhi));
    const Eigen::Matrix3d R_IB = R_IL * Rx(-q(kGamma1)) * Ry(-q(kGamma2));
    const Eigen::Vector3d xi = q.head<3>();
    const Eigen::Vector3d p_A1 = xi + R_IL * Eigen::Vector3d(0, 0, p.rod_length);
    const Eigen::Vector3d p_B = p_A1 + R_IB * p.d_a1b;
    const Eigen::Matrix3d R_CR = R_IB * Rx(-p.dihedral) * Ry(q(kAlphaR));
    const Eigen::Matrix3d R_CL = R_IB * Rx(p.dihedral) * Ry(q(kAlphaL));
    EXPECT_LT((pose.R[KinematicTree::kLoadFrame] - R_IL).norm(), 1e-14);
    EXPECT_LT((pose.R[KinematicTree::kBodyFrame] - R_IB).norm(), 1e-14);
    EXPECT_LT((pose.p[KinematicTree::kBodyFrame] - p_B).norm(), 1e-13);
    EXPECT_LT((pose.R[KinematicTree::kRotorRightFrame] - R_CR).norm(), 1e-14);
    EXPECT_LT((pose.R[KinematicTree::kRotorLeftFrame] - R_CL).norm(), 1e-14);
    EXPECT_LT((pose.p[KinematicTree::kRotorRightFrame] - (p_B + R_IB * p.d_b_right)).norm(), 1e-13);
    EXPECT_LT((pose.p[KinematicTree::kRotorLeftFrame] - (p_B + R_IB * p.d_b_left)).norm(), 1e-13);
  }
}

TEST(KinematicTree, TiltAxesMatchTheGazeboModel) {
  // SDF axes of the tilt joints in body axes: (0, 0.9962, -+0.0872) (model spec 1).
  const KinematicTree tree(test::default_config().vehicle);
  const Vec10 q = Vec10::Zero();
  const TreePose<double> pose = tree.pose(q.data());
  const Eigen::Vector3d right = pose.R[KinematicTree::kRotorRightFrame] * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d left = pose.R[KinematicTree::kRotorLeftFrame] * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(right.y(), 0.9962, 1e-4);
  EXPECT_NEAR(right.z(), -0.0872, 1e-4);
  EXPECT_NEAR(left.z(), 0.0872, 1e-4);
}

TEST(KinematicTree, JacobiansMatchFiniteDifferencesOfPositions) {
  const KinematicTree tree(test::default_config().vehicle);
  std::mt19937_64 rng(11);
  const double h = 1e-6;
  for (int trial = 0; trial < 100; ++trial) {
    const Vec10 q = test::random_q(rng);
    const TreePose<double> pose = tree.pose(q.data());
    for (const TreeBody& b : tree.bodies()) {
      const auto f = static_cast<std::size_t>(b.frame);
      const Eigen::Vector3d com = pose.p[f] + pose.R[f] * b.com;
      Jac<double> jv, jw;
      tree.jacobian(pose, b.frame, com, jv, jw);
      for (int j = 0; j < kNq; ++j) {
        Vec10 qp = q, qm = q;
        qp(j) += h;
        qm(j) -= h;
        const TreePose<double> pp = tree.pose(qp.data()), pm = tree.pose(qm.data());
        const Eigen::Vector3d dp = ((pp.p[f] + pp.R[f] * b.com) - (pm.p[f] + pm.R[f] * b.com)) / (2 * h);
        // World angular velocity column: vee(dR/dq_j R').
        const Eigen::Matrix3d W = (pp.R[f] - pm.R[f]) / (2 * h) * pose.R[f].transpose();
        const Eigen::Vector3d w(W(2, 1), W(0, 2), W(1, 0));
        EXPECT_LT((jv.col(j) - dp).norm(), 1e-8) << "body frame " << b.frame << " coord " << j;
        EXPECT_LT((jw.col(j) - w).norm(), 1e-8) << "body frame " << b.frame << " coord " << j;
      }
    }
  }
}

}  // namespace
}  // namespace tmpc
