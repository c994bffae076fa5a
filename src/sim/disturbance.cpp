#include "tmpc/sim/disturbance.hpp"

#include <algorithm>

namespace tmpc {

DisturbanceSchedule::DisturbanceSchedule(std::vector<DisturbanceStep> steps) : steps_(std::move(steps)) {
  std::stable_sort(steps_.begin(), steps_.end(),
                   [](const DisturbanceStep& a, const DisturbanceStep& b) { return a.time < b.time; });
}

Eigen::Vector3d DisturbanceSchedule::force(double t) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const DisturbanceStep& s : steps_) {
    if (t + 1e-12 < s.time) break;
    f += s.force;
  }
  return f;
}

}  // namespace tmpc
