// Disturbance profiles of a scenario: forces on the load or on the main body (inertial
// axes, at the body's centre of mass), each event one of
//   step   F from `start` on, added to the earlier ones (thesis Table 6.1: 1 N along x
//          at 20 s, y at 40 s, z at 60 s)
//   ramp   from 0 at `start` to F at `end`, held after
//   sine   F sin(2 pi f (t - start) + phase) for start <= t < end
//   gust   a first-order-filtered random force: a command of `magnitude` N along a
//          random direction, redrawn every `redraw` s (seeded), through the lag
//          tau F' + F = command, from `start` to `end` (zero before, decaying after);
//          closed form per segment, so force(t) is a pure function of time
// The force over a plant sub-step is taken at its midpoint (both plants agree).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"

namespace tmpc {

struct DisturbanceEvent {
  enum class Kind { Step, Ramp, Sine, Gust };
  enum class Target { Load, Body };
  Kind kind = Kind::Step;
  Target target = Target::Load;
  double start = 0.0, end = std::numeric_limits<double>::infinity();  ///< s
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< N: step, ramp (final), sine (amplitude)
  double frequency = 0.0, phase = 0.0;              ///< sine: Hz, rad
  double magnitude = 0.0, time_constant = 1.0, redraw = 1.0;  ///< gust: N, s, s
  bool horizontal = false;                          ///< gust: directions in the x-y plane only
  std::uint32_t seed = 1;                           ///< gust
};

class DisturbanceProfile {
 public:
  DisturbanceProfile() = default;
  /// Throws std::invalid_argument naming the event for a bad one (end before start, a
  /// non-positive time constant or redraw interval).
  explicit DisturbanceProfile(std::vector<DisturbanceEvent> events);
  /// The thesis' constant steps on the load.
  static DisturbanceProfile steps(const std::vector<DisturbanceStep>& steps);

  Eigen::Vector3d load_force(double t) const { return force(t, DisturbanceEvent::Target::Load); }
  Eigen::Vector3d body_force(double t) const { return force(t, DisturbanceEvent::Target::Body); }
  /// Start times of the events, sorted and unique: where the metrics' windows begin.
  std::vector<double> event_times() const;
  const std::vector<DisturbanceEvent>& events() const { return events_; }
  bool empty() const { return events_.empty(); }

 private:
  Eigen::Vector3d force(double t, DisturbanceEvent::Target target) const;
  struct GustSegments {
    std::vector<Eigen::Vector3d> command, start_value;  ///< per redraw interval
  };
  std::vector<DisturbanceEvent> events_;
  std::vector<GustSegments> gusts_;  ///< one per event (empty for the other kinds)
};

}  // namespace tmpc
