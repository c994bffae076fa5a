// The reference along a trajectory and the feedforward (5.4).
#include "tmpc/model/reference.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

namespace tmpc {

ReferenceGenerator::ReferenceGenerator(const TiltrotorModel& model, std::shared_ptr<const Trajectory> trajectory,
                                       ReferenceAttitude attitude)
    : model_(&model),
      trajectory_(std::move(trajectory)),
      attitude_(attitude),
      equilibrium_(solve_hover_equilibrium(model, trajectory_->at(0.0).psi)) {}

bool ReferenceGenerator::try_at(double t, ReferencePoint& p) {
  const TrajectoryPoint tp = trajectory_->at(t);
  p = ReferencePoint{};
  p.q.head<3>() = tp.p;
  p.qd.head<3>() = tp.v;
  p.qdd.head<3>() = tp.a;
  p.q(kPsi) = tp.psi;
  p.qd(kPsi) = tp.psi_d;
  p.qdd(kPsi) = tp.psi_dd;
  if (attitude_ == ReferenceAttitude::Trim) {
    // Warm start from the last trim (the yaw moves slowly or not at all); from the
    // hover equilibrium when that fails.
    const Trim start = have_last_ && std::abs(tp.psi - last_yaw_) < 0.1 ? last_ : trim_start(equilibrium_);
    Trim next;
    if (!try_solve_trim(*model_, tp.a, tp.v, tp.psi, start, next) &&
        !try_solve_trim(*model_, tp.a, tp.v, tp.psi, trim_start(equilibrium_), next)) {
      return false;
    }
    last_ = next;
    last_yaw_ = tp.psi;
    have_last_ = true;
    p.q.segment<2>(kPhi) = last_.attitude;
    p.q.segment<4>(kGamma1) = last_.angles;
  } else {
    p.q.segment<4>(kGamma1) = equilibrium_.angles;
  }
  return true;
}

ReferencePoint ReferenceGenerator::at(double t) {
  ReferencePoint p;
  if (!try_at(t, p)) {
    throw std::runtime_error("reference: no trim at t = " + std::to_string(t) + " s of " + trajectory_->description() +
                             " (an acceleration the vehicle cannot fly)");
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
