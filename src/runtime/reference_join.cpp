// Reference join (see reference_join.hpp).
#include "tmpc/runtime/reference_join.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

ReferenceJoinSettings reference_join_settings(const ControllerArtifact& a) {
  ReferenceJoinSettings s;
  if (a.model != ModelKind::Tiltrotor) return s;
  std::vector<int> vel;
  for (int i = 0; i < a.measured; ++i) {
    const StateKind k = a.kinds[static_cast<std::size_t>(i)];
    if (k == StateKind::Position) s.position_rows.push_back(i);
    if (k == StateKind::Velocity) vel.push_back(i);
  }
  if (vel.size() != s.position_rows.size()) return ReferenceJoinSettings{};
  s.velocity_rows = vel;
  const auto n = static_cast<Eigen::Index>(vel.size());
  s.speed_limit.resize(n);
  s.dead_zone.resize(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    s.speed_limit(j) = 0.25 / a.N_x(vel[static_cast<std::size_t>(j)]);
    s.dead_zone(j) = 0.05 / a.N_x(s.position_rows[static_cast<std::size_t>(j)]);
  }
  const Eigen::Vector3d half = 0.5 * (a.envelope.acceleration_max - a.envelope.acceleration_min);
  s.acceleration_limit = half.minCoeff() > 0.0 ? 0.5 * half.minCoeff() : 0.05;
  return s;
}

ReferenceJoin::ReferenceJoin(ReferenceJoinSettings s) : s_(std::move(s)) {
  const auto n = static_cast<Eigen::Index>(s_.position_rows.size());
  if (s_.velocity_rows.size() != s_.position_rows.size() || s_.speed_limit.size() != n || s_.dead_zone.size() != n ||
      (n > 0 && !((s_.speed_limit.array() > 0.0).all() && s_.acceleration_limit > 0.0))) {
    throw std::invalid_argument("reference join: needs a velocity row, a positive speed limit and a dead zone for each "
                                "position row, and a positive acceleration limit");
  }
  g0_ = Eigen::VectorXd::Zero(n);
}

void ReferenceJoin::start(const Eigen::VectorXd& e) {
  active_ = false;
  T_ = 0.0;
  g0_.setZero();
  for (std::size_t j = 0; j < s_.position_rows.size(); ++j) {
    const auto jj = static_cast<Eigen::Index>(j);
    const double g = e(s_.position_rows[j]);
    if (!std::isfinite(g) || std::abs(g) <= s_.dead_zone(jj)) continue;
    g0_(jj) = g;
    T_ = std::max({T_, 1.875 * std::abs(g) / s_.speed_limit(jj), std::sqrt(5.7735 * std::abs(g) / s_.acceleration_limit)});
    active_ = true;
  }
}

void ReferenceJoin::apply(double t, Eigen::VectorXd& e) const {
  if (!active_ || !(t < T_)) return;
  const double tau = std::max(0.0, t / T_);
  const double t2 = tau * tau;
  const double s = t2 * tau * (10.0 - 15.0 * tau + 6.0 * t2);
  const double ds = 30.0 * t2 * (1.0 - 2.0 * tau + t2);  // ds / dtau
  for (std::size_t j = 0; j < s_.position_rows.size(); ++j) {
    const double g = g0_(static_cast<Eigen::Index>(j));
    e(s_.position_rows[j]) -= g * (1.0 - s);
    e(s_.velocity_rows[j]) += g * ds / T_;
  }
}

}  // namespace tmpc
