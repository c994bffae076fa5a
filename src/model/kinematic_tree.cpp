// Kinematic tree of the tiltrotor with its suspended load (model spec section 1).
#include "tmpc/model/kinematic_tree.hpp"

#include "tmpc/model/dual.hpp"

namespace tmpc {

const std::array<const char*, kNq> kCoordNames = {"x",       "y",       "z",       "phi",     "theta",
                                                  "psi",     "gamma_1", "gamma_2", "alpha_r", "alpha_l"};

namespace {
Eigen::Matrix3d rot_x(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
}  // namespace

KinematicTree::KinematicTree(const VehicleParams& p) {
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  frames_.resize(kTreeFrames);
  // 0: load position xi (root translation).
  frames_[0] = TreeFrame{};
  // 1-3: ZYX attitude of the load frame, R_IL = Rz(psi) Ry(theta) Rx(phi).
  frames_[1] = TreeFrame{0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), ez, kPsi};
  frames_[2] = TreeFrame{1, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), ey, kTheta};
  frames_[kLoadFrame] = TreeFrame{2, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), ex, kPhi};
  // 4-5: rod top A1, swing R_IB = R_IL Rx(-gamma_1) Ry(-gamma_2).
  frames_[4] = TreeFrame{kLoadFrame, Eigen::Vector3d(0, 0, p.rod_length), Eigen::Matrix3d::Identity(), -ex, kGamma1};
  frames_[5] = TreeFrame{4, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), -ey, kGamma2};
  // 6: body origin B, offset dA1B in B axes.
  frames_[kBodyFrame] = TreeFrame{5, p.d_a1b, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), -1};
  // 7-8: rotor groups, R_IC = R_IB Rx(-+beta) Ry(alpha).
  frames_[kRotorRightFrame] = TreeFrame{kBodyFrame, p.d_b_right, rot_x(-p.dihedral), ey, kAlphaR};
  frames_[kRotorLeftFrame] = TreeFrame{kBodyFrame, p.d_b_left, rot_x(p.dihedral), ey, kAlphaL};

  const Eigen::Matrix3d rotor_inertia = p.rotor_inertia_about_com();
  bodies_ = {
      TreeBody{kLoadFrame, p.load_mass, Eigen::Vector3d::Zero(), p.load_inertia},
      TreeBody{kBodyFrame, p.body_mass, p.d_b1, p.body_inertia},
      TreeBody{kRotorRightFrame, p.rotor_mass, p.rotor_com, rotor_inertia},
      TreeBody{kRotorLeftFrame, p.rotor_mass, p.rotor_com, rotor_inertia},
  };
}

template <class T>
Mat3<T> axis_rotation(const Eigen::Vector3d& axis, const T& angle) {
  using std::cos;
  using std::sin;
  Mat3<T> k;
  k << T(0.0), T(-axis.z()), T(axis.y()), T(axis.z()), T(0.0), T(-axis.x()), T(-axis.y()), T(axis.x()), T(0.0);
  const T s = sin(angle);
  const T c = cos(angle);
  Mat3<T> r = Mat3<T>::Identity();
  r += k * s;
  r += (k * k) * (T(1.0) - c);
  return r;
}

template <class T>
TreePose<T> KinematicTree::pose(const T* q) const {
  TreePose<T> out;
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    const TreeFrame& f = frames_[k];
    Mat3<T> r;
    Vec3<T> o;
    if (f.parent < 0) {
      r = Mat3<T>::Identity();
      o << q[kX], q[kY], q[kZ];
    } else {
      const auto par = static_cast<std::size_t>(f.parent);
      r = out.R[par] * f.fixed_rotation.cast<T>();
      o = out.p[par] + out.R[par] * f.offset.cast<T>();
    }
    if (f.coord >= 0) r = r * axis_rotation<T>(f.axis, q[f.coord]);
    out.R[k] = r;
    out.p[k] = o;
  }
  return out;
}

template <class T>
void KinematicTree::jacobian(const TreePose<T>& pose, int frame, const Vec3<T>& point, Jac<T>& jv,
                             Jac<T>& jw) const {
  jv.setZero();
  jw.setZero();
  for (int k = frame; k >= 0; k = frames_[static_cast<std::size_t>(k)].parent) {
    const auto ku = static_cast<std::size_t>(k);
    const TreeFrame& f = frames_[ku];
    if (f.parent < 0) {
      jv(0, kX) = T(1.0);
      jv(1, kY) = T(1.0);
      jv(2, kZ) = T(1.0);
    }
    if (f.coord < 0) continue;
    const Vec3<T> z = pose.R[ku] * f.axis.cast<T>();
    jv.col(f.coord) += z.cross(point - pose.p[ku]);
    jw.col(f.coord) += z;
  }
}

#define TMPC_INSTANTIATE_TREE(T)                                                                   \
  template Mat3<T> axis_rotation<T>(const Eigen::Vector3d&, const T&);                             \
  template TreePose<T> KinematicTree::pose<T>(const T*) const;                                     \
  template void KinematicTree::jacobian<T>(const TreePose<T>&, int, const Vec3<T>&, Jac<T>&, Jac<T>&) \
      const;
TMPC_INSTANTIATE_TREE(double)
TMPC_INSTANTIATE_TREE(D1)
TMPC_INSTANTIATE_TREE(D2)
#undef TMPC_INSTANTIATE_TREE

}  // namespace tmpc
