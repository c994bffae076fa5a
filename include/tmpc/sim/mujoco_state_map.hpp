// Mapping between our coordinates and MuJoCo's for the tiltrotor (model spec 8):
//   ours:    q = (xi, phi, theta, psi, gamma_1, gamma_2, alpha_r, alpha_l), q' with
//            Euler-angle rates eta' (ZYX, R_IL = Rz(psi) Ry(theta) Rx(phi))
//   MuJoCo:  qpos = (xi, quat(R_IL) [w x y z], gamma_1, gamma_2, alpha_r, alpha_l),
//            qvel = (xi', w_L in load axes, joint rates)
//   w_L = E(eta) eta',  E = [1 0 -s_th; 0 c_ph s_ph c_th; 0 -s_ph c_ph c_th]
//   accelerations: eta'' = E^-1 (w_L' - E' eta')
// Pure math: it does not need MuJoCo and is tested in every build.
#pragma once

#include <Eigen/Core>

#include "tmpc/model/dynamics.hpp"

namespace tmpc::mujoco_map {

constexpr int kNqpos = 11;
constexpr int kNqvel = 10;
using Qpos = Eigen::Matrix<double, kNqpos, 1>;
using Qvel = Eigen::Matrix<double, kNqvel, 1>;

/// E(eta): Euler-angle (ZYX) rates to body angular velocity.
Eigen::Matrix3d euler_rate_matrix(double phi, double theta);

/// Our state x = (q, q') to MuJoCo's (qpos, qvel).
void to_mujoco(const State20& x, Qpos& qpos, Qvel& qvel);
/// MuJoCo's (qpos, qvel) to our state; Euler angles from the quaternion (theta in
/// (-pi/2, pi/2)), yaw unwrapped towards `yaw_hint`.
State20 from_mujoco(const Qpos& qpos, const Qvel& qvel, double yaw_hint = 0.0);
/// MuJoCo's qacc at state x to our q''.
Vec10 acceleration_from_mujoco(const State20& x, const Qvel& qacc);

}  // namespace tmpc::mujoco_map
