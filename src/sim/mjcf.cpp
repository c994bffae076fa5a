// MJCF generation for the MuJoCo plant from the vehicle parameters.
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "tmpc/sim/mujoco_plant.hpp"

namespace tmpc {

namespace {

std::string num(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}
std::string vec(const Eigen::Vector3d& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }
/// MuJoCo's fullinertia order: Ixx Iyy Izz Ixy Ixz Iyz.
std::string full_inertia(const Eigen::Matrix3d& I) {
  return num(I(0, 0)) + " " + num(I(1, 1)) + " " + num(I(2, 2)) + " " + num(I(0, 1)) + " " + num(I(0, 2)) + " " +
         num(I(1, 2));
}
/// Rigid-body inertia: positive definite with the triangle inequalities.
void check_physical(const Eigen::Matrix3d& I, const std::string& what) {
  const Eigen::Vector3d e = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  const bool triangle = e(0) + e(1) >= e(2) * (1.0 - 1e-12) && e(0) + e(2) >= e(1) && e(1) + e(2) >= e(0);
  if (e(0) <= 0.0 || !triangle) {
    std::ostringstream os;
    os << what << " (principal moments " << e.transpose() << ") is not the inertia of a rigid body"
       << " (A + B >= C fails)";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

std::string make_mjcf(const VehicleParams& p, double timestep) {
  if (p.rotor_inertia_reference == RotorInertiaReference::Pivot) {
    try {
      check_physical(p.rotor_inertia_about_com(), "");
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument(
          "MuJoCo plant: parameter set S2 (vehicle.rotor.inertia_about: pivot) leaves a rotor-group inertia about "
          "the CoM that is not a rigid body (Ixx + Iyy < Izz); MuJoCo rejects it. Use inertia_about: com (S1) or "
          "the el plant.");
    }
  }
  check_physical(p.load_inertia, "MuJoCo plant: vehicle.load.inertia");
  check_physical(p.body_inertia, "MuJoCo plant: vehicle.body.inertia");
  check_physical(p.rotor_inertia_about_com(), "MuJoCo plant: vehicle.rotor.inertia");
  for (int i = 0; i < 6; ++i) {
    if (p.friction[static_cast<std::size_t>(i)] != 0.0) {
      throw std::invalid_argument("MuJoCo plant: vehicle.friction[" + std::to_string(i) +
                                  "] must be 0: friction on the load's position or Euler rates has no MuJoCo "
                                  "free-joint equivalent");
    }
  }
  const double mu_g1 = p.friction[kGamma1], mu_g2 = p.friction[kGamma2];
  const Eigen::Vector3d main_pos = Eigen::Vector3d(0, 0, p.rod_length) + p.d_a1b;
  const Eigen::Matrix3d Ir = p.rotor_inertia_about_com();
  // The two rotor groups differ in side, roll sign (Rx(-+beta)), damping and spin.
  struct Rotor {
    const char* side;
    const char* joint;
    const Eigen::Vector3d& pivot;
    double roll_sign, damping, spin;
  };
  const Rotor rotors[2] = {{"right", "alpha_r", p.d_b_right, -1.0, p.friction[kAlphaR], p.spin_right},
                           {"left", "alpha_l", p.d_b_left, 1.0, p.friction[kAlphaL], p.spin_left}};

  std::ostringstream x;
  x << "<mujoco model=\"tiltrotor_load\">\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"false\" autolimits=\"true\"/>\n"
    << "  <option timestep=\"" << num(timestep) << "\" integrator=\"RK4\" gravity=\"0 0 " << num(-p.gravity)
    << "\"/>\n"
    << "  <worldbody>\n"
    << "    <body name=\"load\">\n"
    << "      <freejoint name=\"root\"/>\n"
    << "      <inertial pos=\"0 0 0\" mass=\"" << num(p.load_mass) << "\" fullinertia=\"" << full_inertia(p.load_inertia)
    << "\"/>\n"
    << "      <body name=\"main\" pos=\"" << vec(main_pos) << "\">\n"
    << "        <joint name=\"gamma_1\" type=\"hinge\" pos=\"" << vec(-p.d_a1b) << "\" axis=\"-1 0 0\" damping=\""
    << num(mu_g1) << "\"/>\n"
    << "        <joint name=\"gamma_2\" type=\"hinge\" pos=\"" << vec(-p.d_a1b) << "\" axis=\"0 -1 0\" damping=\""
    << num(mu_g2) << "\"/>\n"
    << "        <inertial pos=\"" << vec(p.d_b1) << "\" mass=\"" << num(p.body_mass) << "\" fullinertia=\""
    << full_inertia(p.body_inertia) << "\"/>\n";
  for (const Rotor& r : rotors) {
    const double h = 0.5 * r.roll_sign * p.dihedral;
    x << "        <body name=\"rotor_" << r.side << "\" pos=\"" << vec(r.pivot) << "\" quat=\"" << num(std::cos(h))
      << " " << num(std::sin(h)) << " 0 0\">\n"
      << "          <joint name=\"" << r.joint << "\" type=\"hinge\" axis=\"0 1 0\" damping=\"" << num(r.damping)
      << "\"/>\n"
      << "          <inertial pos=\"" << vec(p.rotor_com) << "\" mass=\"" << num(p.rotor_mass) << "\" fullinertia=\""
      << full_inertia(Ir) << "\"/>\n"
      << "          <site name=\"thrust_" << r.side << "\" pos=\"0 0 0\"/>\n"
      << "        </body>\n";
  }
  x << "      </body>\n"
    << "    </body>\n"
    << "  </worldbody>\n"
    << "  <actuator>\n";
  for (const Rotor& r : rotors) {
    x << "    <general name=\"f_" << r.side[0] << "\" site=\"thrust_" << r.side << "\" gear=\"0 0 1 0 0 "
      << num(r.spin * p.drag_torque_ratio) << "\"/>\n";
  }
  for (const Rotor& r : rotors) {
    x << "    <motor name=\"tau_" << r.side[0] << "\" joint=\"" << r.joint << "\" gear=\"1\"/>\n";
  }
  x << "  </actuator>\n"
    << "</mujoco>\n";
  return x.str();
}

}  // namespace tmpc
