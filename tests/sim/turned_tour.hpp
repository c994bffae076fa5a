// A waypoint tour with two force steps on the load, the whole mission (its yaw and its
// forces too) turned by an angle about the vertical through the origin: the oracle of
// the any-yaw tests. The vehicle, gravity and the plant do not change when a mission
// turns, so the turned mission flies with the same errors in the reference's yaw frame.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "tmpc/sim/scenario.hpp"

namespace tmpc::test {

inline Scenario turned_tour(double a) {
  const double c = std::cos(a), s = std::sin(a);
  auto turn = [&](double x, double y, double z) {
    char b[96];
    std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", c * x - s * y, s * x + c * y, z);
    return std::string(b);
  };
  const std::string yaml = "name: turned_tour\nduration: 15.0\ntrajectory: {type: waypoints, points: [" +
                           turn(0, 0, 1) + ", " + turn(4, 0, 2) + ", " + turn(4, 4, 3) +
                           "], max_speed: 0.6, max_acceleration: 0.05, yaw: " + std::to_string(a) +
                           "}\ndisturbances:\n  - {type: step, time: 4.0, force: " + turn(1.0, 0, 0) +
                           "}\n  - {type: step, time: 9.0, force: " + turn(0, -1.2, 0.3) + "}\n";
  return scenario_from_string(yaml, "turned_tour.yaml");
}

}  // namespace tmpc::test
