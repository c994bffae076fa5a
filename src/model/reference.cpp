// Helix reference (thesis 6.2) and feedforward (5.4).
#include "tmpc/model/reference.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace tmpc {

HelixTrajectory::HelixTrajectory(const HelixReference& helix, const Eigen::Vector4d& equilibrium_angles)
    : helix_(helix), angles_(equilibrium_angles) {}

ReferencePoint HelixTrajectory::at(double t) const {
  const double w = helix_.angular_rate;
  const double c = std::cos(w * t);
  const double s = std::sin(w * t);
  const double r = helix_.radius;
  const double a = helix_.z_amplitude;
  ReferencePoint p;
  p.q << helix_.center_x + r * c, helix_.center_y + r * s, helix_.z_offset - a * c, 0.0, 0.0, helix_.yaw, angles_(0),
      angles_(1), angles_(2), angles_(3);
  p.qd.head<3>() << -r * w * s, r * w * c, a * w * s;
  p.qdd.head<3>() << -r * w * w * c, -r * w * w * s, a * w * w * c;
  return p;
}

Eigen::Vector4d feedforward(const TiltrotorModel& model, const ReferencePoint& r) {
  const DynamicsTerms<double> t = model.terms<double>(r.q.data(), r.qd.data());
  const Vec10 rhs = t.M * r.qdd + t.c + model.friction_matrix() * r.qd + t.G;
  // Least-squares (pseudo-inverse) solution; L_in has full column rank.
  return t.L_in.completeOrthogonalDecomposition().solve(rhs);
}

}  // namespace tmpc
