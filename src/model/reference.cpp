// Helix reference (thesis 6.2) and feedforward (5.4).
#include "tmpc/model/reference.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace tmpc {

HelixTrajectory::HelixTrajectory(const HelixReference& helix, const TiltrotorModel& model)
    : helix_(helix), model_(&model), equilibrium_(solve_hover_equilibrium(model, helix.yaw)) {}

ReferencePoint HelixTrajectory::at(double t) const {
  const double w = helix_.angular_rate;
  const double c = std::cos(w * t);
  const double s = std::sin(w * t);
  const double r = helix_.radius;
  const double a = helix_.z_amplitude;
  ReferencePoint p;
  p.q.head<3>() << helix_.center_x + r * c, helix_.center_y + r * s, helix_.z_offset - a * c;
  p.q(kPsi) = helix_.yaw;
  p.qd.head<3>() << -r * w * s, r * w * c, a * w * s;
  p.qdd.head<3>() << -r * w * w * c, -r * w * w * s, a * w * w * c;
  if (helix_.attitude == ReferenceAttitude::Trim) {
    const Trim trim = solve_trim(*model_, p.qdd.head<3>(), p.qd.head<3>(), helix_.yaw, equilibrium_);
    p.q.segment<2>(kPhi) = trim.attitude;
    p.q.segment<4>(kGamma1) = trim.angles;
  } else {
    p.q.segment<4>(kGamma1) = equilibrium_.angles;
  }
  return p;
}

Eigen::Vector4d feedforward(const TiltrotorModel& model, const ReferencePoint& r) {
  const DynamicsTerms<double> t = model.terms<double>(r.q.data(), r.qd.data());
  const Vec10 rhs = t.M * r.qdd + t.c + model.friction_matrix() * r.qd + t.G;
  // Least-squares (pseudo-inverse) solution; L_in has full column rank. At a trim
  // point the residual is zero.
  return t.L_in.completeOrthogonalDecomposition().solve(rhs);
}

}  // namespace tmpc
