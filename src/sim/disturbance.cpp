// Disturbance profiles (see disturbance.hpp).
#include "tmpc/sim/disturbance.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace tmpc {

namespace {
/// Longest gust precomputed: a day of flight (beyond, the last command holds).
constexpr double kGustHorizon = 86400.0;
}  // namespace

DisturbanceProfile::DisturbanceProfile(std::vector<DisturbanceEvent> events) : events_(std::move(events)) {
  gusts_.resize(events_.size());
  for (std::size_t k = 0; k < events_.size(); ++k) {
    const DisturbanceEvent& e = events_[k];
    const std::string which = "disturbance " + std::to_string(k);
    if (!(e.start >= 0.0) || !(e.end > e.start)) throw std::invalid_argument(which + ": end must come after start >= 0");
    if (!e.force.allFinite()) throw std::invalid_argument(which + ": non-finite force");
    if (e.kind == DisturbanceEvent::Kind::Ramp && !std::isfinite(e.end)) throw std::invalid_argument(which + ": a ramp needs an end");
    if (e.kind != DisturbanceEvent::Kind::Gust) continue;
    if (!(e.time_constant > 0.0) || !(e.redraw > 0.0) || !(e.magnitude >= 0.0)) {
      throw std::invalid_argument(which + ": a gust needs magnitude >= 0, time_constant > 0 and redraw > 0");
    }
    // Commands per redraw interval and the filter's state at each interval's start.
    const double span = std::min(e.end, e.start + kGustHorizon) - e.start;
    const std::size_t segments = static_cast<std::size_t>(std::ceil(span / e.redraw)) + 1;
    std::mt19937_64 rng(e.seed);
    std::normal_distribution<double> g(0.0, 1.0);
    GustSegments& s = gusts_[k];
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < segments; ++i) {
      Eigen::Vector3d d(g(rng), g(rng), e.horizontal ? 0.0 : g(rng));
      if (d.norm() < 1e-12) d = Eigen::Vector3d::UnitX();
      const Eigen::Vector3d c = e.magnitude * d.normalized();
      s.command.push_back(c);
      s.start_value.push_back(f);
      f = c + (f - c) * std::exp(-e.redraw / e.time_constant);
    }
  }
}

DisturbanceProfile DisturbanceProfile::steps(const std::vector<DisturbanceStep>& steps) {
  std::vector<DisturbanceEvent> events;
  for (const DisturbanceStep& s : steps) {
    DisturbanceEvent e;
    e.kind = DisturbanceEvent::Kind::Step;
    e.start = s.time;
    e.force = s.force;
    events.push_back(e);
  }
  return DisturbanceProfile(std::move(events));
}

std::vector<double> DisturbanceProfile::event_times() const {
  std::vector<double> t;
  for (const DisturbanceEvent& e : events_) t.push_back(e.start);
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  return t;
}

Eigen::Vector3d DisturbanceProfile::force(double t, DisturbanceEvent::Target target) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < events_.size(); ++k) {
    const DisturbanceEvent& e = events_[k];
    if (e.target != target || t + 1e-12 < e.start) continue;
    switch (e.kind) {
      case DisturbanceEvent::Kind::Step:
        if (t < e.end) f += e.force;
        break;
      case DisturbanceEvent::Kind::Ramp:
        f += e.force * std::min(1.0, (t - e.start) / (e.end - e.start));
        break;
      case DisturbanceEvent::Kind::Sine:
        if (t < e.end) f += e.force * std::sin(2.0 * M_PI * e.frequency * (t - e.start) + e.phase);
        break;
      case DisturbanceEvent::Kind::Gust: {
        const GustSegments& s = gusts_[k];
        const double tau = std::min(t, e.end) - e.start;
        const std::size_t i = std::min(s.command.size() - 1, static_cast<std::size_t>(tau / e.redraw));
        const double into = tau - static_cast<double>(i) * e.redraw;
        const Eigen::Vector3d& c = s.command[i];
        Eigen::Vector3d g = c + (s.start_value[i] - c) * std::exp(-into / e.time_constant);
        if (t > e.end) g *= std::exp(-(t - e.end) / e.time_constant);  // the gust dies out
        f += g;
        break;
      }
    }
  }
  return f;
}

}  // namespace tmpc
