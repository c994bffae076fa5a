// Yawing into a force on the load (see yaw_governor.hpp).
#include "tmpc/runtime/yaw_governor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tmpc {

YawGovernorSettings yaw_governor_settings(const ControllerArtifact& a, const Trajectory& t, double duration,
                                          double tilt_on) {
  if (a.model != ModelKind::Tiltrotor || !a.envelope.any_yaw()) {
    throw std::invalid_argument("yaw into the force: needs an any-yaw tiltrotor design (envelope.yaw_rate_max)");
  }
  if (!(tilt_on > 0.0 && tilt_on < 1.0)) throw std::invalid_argument("yaw into the force: tilt_on must be in (0, 1)");
  YawGovernorSettings s;
  int angle = 0;
  for (std::size_t i = 0; i < a.kinds.size() && angle < 2; ++i) {
    if (a.kinds[i] != StateKind::Angle) continue;
    (angle++ == 0 ? s.phi_bound : s.theta_bound) = 1.0 / a.N_x(static_cast<Eigen::Index>(i));
  }
  double own = 0.0;
  for (double tt = 0.0; tt <= duration + 1e-9; tt += a.sample_time) own = std::max(own, std::abs(t.at(tt).psi_d));
  s.rate_max = a.envelope.yaw_rate_max - own - 0.01;
  if (!(s.rate_max > 0.0)) {
    throw std::invalid_argument("yaw into the force: the trajectory turns at " + std::to_string(own) +
                                " rad/s, which leaves no rate under the envelope's " +
                                std::to_string(a.envelope.yaw_rate_max) + " rad/s");
  }
  s.force_on = std::tan(tilt_on * std::min(s.phi_bound, s.theta_bound)) * a.vehicle.load_mass * 9.81;
  return s;
}

YawGovernor::YawGovernor(YawGovernorSettings s) : s_(s) {
  if (!(s_.rate_max > 0.0 && s_.acceleration_max > 0.0 && s_.force_on >= 0.0 && s_.phi_bound > 0.0 &&
        s_.theta_bound > 0.0)) {
    throw std::invalid_argument("yaw governor: rate and acceleration limits and the bounds must be positive");
  }
}

void YawGovernor::reset() {
  offset_ = rate_ = acc_ = target_ = 0.0;
  active_ = false;
}

void YawGovernor::update(const Eigen::Vector2d& d_frame, double psi_frame, double psi_mission, double dt) {
  const double c = std::cos(psi_frame), s = std::sin(psi_frame);
  const Eigen::Vector2d F(c * d_frame.x() - s * d_frame.y(), s * d_frame.x() + c * d_frame.y());  // world axes
  // Needed: the force's larger component in the mission's yaw frame past force_on.
  const double cm = std::cos(psi_mission), sm = std::sin(psi_mission);
  const double larger = std::max(std::abs(cm * F.x() + sm * F.y()), std::abs(-sm * F.x() + cm * F.y()));
  if (!std::isfinite(larger)) return;  // a non-finite estimate moves nothing
  active_ = larger >= s_.force_on || (active_ && larger >= 0.8 * s_.force_on);
  double target = 0.0;
  if (active_) {
    // The four yaws with F on a diagonal of the box; the one nearest the mission's yaw
    // (the current target's unless another is 0.3 rad nearer: no flipping between two).
    const double beta0 = std::atan2(s_.phi_bound, s_.theta_bound), dir = std::atan2(F.y(), F.x());
    double best = 1e300;
    for (double beta : {beta0, M_PI - beta0, -beta0, beta0 - M_PI}) {
      const double off = std::remainder(dir - beta - psi_mission, 2 * M_PI);
      const double cost = std::abs(off) - (std::abs(off - target_) < 0.3 ? 0.3 : 0.0);
      if (cost < best) {
        best = cost;
        target = off;
      }
    }
  }
  target_ = target;
  // The rate that stops at the target under the acceleration limit, reached at most
  // acceleration_max dt away from the current rate.
  const double e = target_ - offset_;
  const double want = std::copysign(std::min(s_.rate_max, std::sqrt(2.0 * s_.acceleration_max * std::abs(e))), e);
  const double next = std::clamp(want, rate_ - s_.acceleration_max * dt, rate_ + s_.acceleration_max * dt);
  acc_ = (next - rate_) / dt;
  rate_ = next;
  offset_ += rate_ * dt;
}

GovernedTrajectory::GovernedTrajectory(std::shared_ptr<const Trajectory> base, const YawGovernor* g)
    : base_(std::move(base)), g_(g) {}

TrajectoryPoint GovernedTrajectory::at(double t) const {
  TrajectoryPoint p = base_->at(t);
  p.psi += g_->offset();
  p.psi_d += g_->rate();
  p.psi_dd += g_->acceleration();
  return p;
}

}  // namespace tmpc
