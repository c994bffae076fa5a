// Pre-flight check of a trajectory against the artifact (see preflight.hpp).
#include "tmpc/runtime/preflight.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tmpc/model/reference.hpp"

namespace tmpc {

PreflightReport check_flight(const ControllerArtifact& a, const Trajectory& t, double duration) {
  PreflightReport r;
  r.acceleration_min.setConstant(1e300);
  r.acceleration_max.setConstant(-1e300);
  r.feedforward_min = Eigen::VectorXd::Constant(a.m, 1e300);
  r.feedforward_max = Eigen::VectorXd::Constant(a.m, -1e300);
  std::ostringstream os;
  auto refuse = [&](double time, const std::string& what) {
    if (!r.ok) return;
    r.ok = false;
    r.time = time;
    std::ostringstream m;
    m << t.description() << ": t = " << time << " s: " << what;
    r.message = m.str();
  };
  if (a.model == ModelKind::Linear) {
    for (double tt = 0.0; tt <= duration + 1e-9; tt += a.sample_time) {
      const TrajectoryPoint p = t.at(tt);
      if (p.p.norm() > 0.0 || p.v.norm() > 0.0) {
        refuse(tt, "a linear model regulates to the origin: the trajectory must hover there");
        break;
      }
    }
    if (r.ok) r.message = "hover at the origin for " + std::to_string(duration) + " s";
    return r;
  }
  const TiltrotorModel model(a.vehicle);
  ReferenceGenerator gen(model, std::shared_ptr<const Trajectory>(&t, [](const Trajectory*) {}), a.attitude);
  const EnvelopeSettings& e = a.envelope;
  const double tol = 1e-9;
  static const char* const axis = "xyz";
  const long periods = std::lround(duration / a.sample_time);
  for (long k = 0; k <= periods && r.ok; ++k) {
    const double tt = static_cast<double>(k) * a.sample_time;
    const TrajectoryPoint p = t.at(tt);
    const Eigen::Vector3d acc = e.in_design_frame(p.a, p.psi);  // the LPV box is in the design's frame
    r.acceleration_min = r.acceleration_min.cwiseMin(acc);
    r.acceleration_max = r.acceleration_max.cwiseMax(acc);
    r.speed_max = std::max(r.speed_max, p.v.norm());
    for (int i = 0; i < 3; ++i) {
      if (acc(i) < e.acceleration_min(i) - tol || acc(i) > e.acceleration_max(i) + tol) {
        std::ostringstream m;
        const bool turned = e.any_yaw() && i < 2 && std::remainder(p.psi - e.yaw, 2.0 * M_PI) != 0.0;
        m << "acceleration " << axis[i] << " = " << acc(i) << " m/s^2"
          << (turned ? " (in the reference's yaw frame)" : "") << " outside the envelope [" << e.acceleration_min(i)
          << ", " << e.acceleration_max(i) << "]";
        refuse(tt, m.str());
      }
    }
    if (p.v.norm() > e.speed_max + tol) {
      std::ostringstream m;
      m << "speed " << p.v.norm() << " m/s above the envelope's " << e.speed_max << " m/s";
      refuse(tt, m.str());
    }
    if (e.any_yaw()) {
      if (std::abs(p.psi_d) > e.yaw_rate_max + tol) {
        std::ostringstream m;
        m << "yaw rate " << p.psi_d << " rad/s beyond the envelope's +- " << e.yaw_rate_max << " rad/s";
        refuse(tt, m.str());
      }
    } else if (std::abs(std::remainder(p.psi - e.yaw, 2.0 * M_PI)) > e.yaw_tolerance + tol) {
      std::ostringstream m;
      m << "yaw " << p.psi << " rad outside the envelope's " << e.yaw << " +- " << e.yaw_tolerance << " rad";
      refuse(tt, m.str());
    }
    if (!r.ok) break;
    ReferencePoint ref;
    if (!gen.try_at(tt, ref)) {
      refuse(tt, "no trim for this acceleration");
      break;
    }
    const Eigen::Vector4d u = feedforward(model, ref);
    for (int i = 0; i < a.m; ++i) {
      r.feedforward_min(i) = std::min(r.feedforward_min(i), u(i));
      r.feedforward_max(i) = std::max(r.feedforward_max(i), u(i));
      const double slack = 1e-6 * (a.input_max(i) - a.input_min(i));
      if (u(i) < a.feedforward_min(i) - slack || u(i) > a.feedforward_max(i) + slack) {
        std::ostringstream m;
        m << "feedforward " << a.input_names[static_cast<std::size_t>(i)] << " = " << u(i) << " outside ["
          << a.feedforward_min(i) << ", " << a.feedforward_max(i) << "], the range the input set was tightened for";
        refuse(tt, m.str());
      }
    }
  }
  if (r.ok) {
    os << t.description() << ": inside the envelope for " << duration << " s (acceleration [" << r.acceleration_min.transpose()
       << "] to [" << r.acceleration_max.transpose() << "] m/s^2, speed up to " << r.speed_max << " m/s)";
    r.message = os.str();
  }
  return r;
}

void require_flight(const ControllerArtifact& a, const Trajectory& t, double duration, const std::string& what) {
  const PreflightReport r = check_flight(a, t, duration);
  if (!r.ok) throw std::invalid_argument(what + ": refused before take-off: " + r.message);
}

}  // namespace tmpc
