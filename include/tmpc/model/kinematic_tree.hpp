// Kinematic tree of the load-perspective tiltrotor (model spec section 1):
//
//   I --(xi, then ZYX eta)--> L (load) --(rod l along z_L)--> A1
//     --(Rx(-gamma_1) Ry(-gamma_2))--> B (offset dA1B in B axes)
//     --(dB2, Rx(-beta) Ry(alpha_r))--> C_R,   --(dB3, Rx(+beta) Ry(alpha_l))--> C_L
//
// Each frame k is reached from its parent by a translation (parent axes), a fixed
// rotation and at most one revolute joint about a unit axis of its own axes:
//   R_k = R_parent Rf_k Rot(a_k, q_j),  p_k = p_parent + R_parent o_k.
// The root is translated by xi = (q_0, q_1, q_2). Geometric Jacobians follow from
// the tree: a revolute joint with world axis z at origin o adds z x (p - o) to the
// translational column and z to the angular column of its coordinate.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "tmpc/model/config.hpp"

namespace tmpc {

constexpr int kNq = 10;  ///< generalized coordinates
constexpr int kNx = 20;  ///< mechanical states (q, q-dot)
constexpr int kNu = 4;   ///< inputs f_r f_l tau_r tau_l
constexpr int kNd = 3;   ///< disturbance force on the load

/// Coordinate order used everywhere (DESIGN.md section 3, E10).
enum Coord : int { kX = 0, kY, kZ, kPhi, kTheta, kPsi, kGamma1, kGamma2, kAlphaR, kAlphaL };

/// Names of the 10 coordinates, in order.
extern const std::array<const char*, kNq> kCoordNames;

template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
template <class T>
using Mat3 = Eigen::Matrix<T, 3, 3>;
template <class T>
using Jac = Eigen::Matrix<T, 3, kNq>;

/// One frame of the tree.
struct TreeFrame {
  int parent = -1;                                        // -1: root, translated by xi
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();       // origin in parent axes
  Eigen::Matrix3d fixed_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();         // joint axis in own axes
  int coord = -1;                                         // joint coordinate, -1: none
};

/// A rigid body attached to a frame.
struct TreeBody {
  int frame = 0;
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();         // in frame axes
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();     // about the CoM, frame axes
};

/// Frames of the tree (load translation, its three ZYX rotations, two swing joints,
/// body, two rotor groups).
constexpr int kTreeFrames = 9;

/// World pose of every frame for one configuration q (fixed size: the real-time path
/// evaluates it every period without allocating).
template <class T>
struct TreePose {
  std::array<Mat3<T>, kTreeFrames> R;
  std::array<Vec3<T>, kTreeFrames> p;
};

class KinematicTree {
 public:
  /// Frames used by the generalized forces.
  enum FrameId : int { kLoadFrame = 3, kBodyFrame = 6, kRotorRightFrame = 7, kRotorLeftFrame = 8 };
  /// Bodies in the order load, main body, right rotor group, left rotor group.
  enum BodyId : int { kLoad = 0, kBody = 1, kRotorRight = 2, kRotorLeft = 3 };

  explicit KinematicTree(const VehicleParams& p);

  const std::vector<TreeFrame>& frames() const { return frames_; }
  const std::vector<TreeBody>& bodies() const { return bodies_; }

  /// World rotation and origin of every frame.
  template <class T>
  TreePose<T> pose(const T* q) const;

  /// Translational (Jv) and world angular (Jw) Jacobians of a point fixed to
  /// `frame` at world position `point`, for the pose computed by pose().
  template <class T>
  void jacobian(const TreePose<T>& pose, int frame, const Vec3<T>& point, Jac<T>& jv, Jac<T>& jw) const;

 private:
  std::vector<TreeFrame> frames_;
  std::vector<TreeBody> bodies_;
};

/// Elementary rotation about a unit axis (Rodrigues).
template <class T>
Mat3<T> axis_rotation(const Eigen::Vector3d& axis, const T& angle);

}  // namespace tmpc
