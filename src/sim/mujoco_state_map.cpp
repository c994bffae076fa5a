// Coordinates of the MuJoCo plant <-> ours (model spec 8).
#include "tmpc/sim/mujoco_state_map.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace tmpc::mujoco_map {

Eigen::Matrix3d euler_rate_matrix(double phi, double theta) {
  const double sp = std::sin(phi), cp = std::cos(phi), st = std::sin(theta), ct = std::cos(theta);
  Eigen::Matrix3d E;
  E << 1.0, 0.0, -st, 0.0, cp, sp * ct, 0.0, -sp, cp * ct;
  return E;
}

namespace {
/// d/dt E(phi(t), theta(t)) for rates (phid, thetad).
Eigen::Matrix3d euler_rate_matrix_dot(double phi, double theta, double phid, double thetad) {
  const double sp = std::sin(phi), cp = std::cos(phi), st = std::sin(theta), ct = std::cos(theta);
  Eigen::Matrix3d Ed;
  Ed << 0.0, 0.0, -ct * thetad, 0.0, -sp * phid, cp * ct * phid - sp * st * thetad, 0.0, -cp * phid,
      -sp * ct * phid - cp * st * thetad;
  return Ed;
}
}  // namespace

void to_mujoco(const State20& x, Qpos& qpos, Qvel& qvel) {
  const double phi = x(kPhi), theta = x(kTheta), psi = x(kPsi);
  const Eigen::Quaterniond quat = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX());
  qpos.head<3>() = x.head<3>();
  qpos(3) = quat.w();
  qpos(4) = quat.x();
  qpos(5) = quat.y();
  qpos(6) = quat.z();
  qpos.tail<4>() = x.segment<4>(kGamma1);
  qvel.head<3>() = x.segment<3>(kNq + kX);
  qvel.segment<3>(3) = euler_rate_matrix(phi, theta) * x.segment<3>(kNq + kPhi);
  qvel.tail<4>() = x.segment<4>(kNq + kGamma1);
}

State20 from_mujoco(const Qpos& qpos, const Qvel& qvel, double yaw_hint) {
  const Eigen::Quaterniond quat(qpos(3), qpos(4), qpos(5), qpos(6));
  const Eigen::Matrix3d R = quat.normalized().toRotationMatrix();
  // R = Rz(psi) Ry(theta) Rx(phi): R20 = -s_th, R21 = c_th s_ph, R22 = c_th c_ph, R10 = s_ps c_th, R00 = c_ps c_th.
  const double theta = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double phi = std::atan2(R(2, 1), R(2, 2));
  double psi = std::atan2(R(1, 0), R(0, 0));
  psi += 2.0 * M_PI * std::round((yaw_hint - psi) / (2.0 * M_PI));
  State20 x;
  x.head<3>() = qpos.head<3>();
  x(kPhi) = phi;
  x(kTheta) = theta;
  x(kPsi) = psi;
  x.segment<4>(kGamma1) = qpos.tail<4>();
  x.segment<3>(kNq + kX) = qvel.head<3>();
  x.segment<3>(kNq + kPhi) = euler_rate_matrix(phi, theta).lu().solve(qvel.segment<3>(3));
  x.segment<4>(kNq + kGamma1) = qvel.tail<4>();
  return x;
}

Vec10 acceleration_from_mujoco(const State20& x, const Qvel& qacc) {
  const double phi = x(kPhi), theta = x(kTheta);
  const Eigen::Vector3d etad = x.segment<3>(kNq + kPhi);
  const Eigen::Matrix3d Ed = euler_rate_matrix_dot(phi, theta, etad(0), etad(1));
  Vec10 qdd;
  qdd.head<3>() = qacc.head<3>();
  qdd.segment<3>(kPhi) = euler_rate_matrix(phi, theta).lu().solve(qacc.segment<3>(3) - Ed * etad);
  qdd.tail<4>() = qacc.tail<4>();
  return qdd;
}

}  // namespace tmpc::mujoco_map
