// Disturbance schedule: constant forces on the load switched on at given times and
// added to the earlier ones (thesis Table 6.1: 1 N along x at 20 s, y at 40 s, z at 60 s).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"

namespace tmpc {

class DisturbanceSchedule {
 public:
  DisturbanceSchedule() = default;
  explicit DisturbanceSchedule(std::vector<DisturbanceStep> steps);

  /// Total force on the load at time t (N, inertial axes); steps act from their time on.
  Eigen::Vector3d force(double t) const;
  const std::vector<DisturbanceStep>& steps() const { return steps_; }

 private:
  std::vector<DisturbanceStep> steps_;
};

}  // namespace tmpc
