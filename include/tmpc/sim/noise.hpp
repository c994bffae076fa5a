// Sensor noise of a scenario: per state group (positions, angles with the yaw,
// velocities, angular rates) a white Gaussian part of standard deviation `white` and a
// constant `bias`, from a seeded generator; added to the measured state the controller
// is sent, never to the plant. apply() allocates nothing.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/state_layout.hpp"

namespace tmpc {

struct NoiseSpec {
  std::array<double, 4> white{};  ///< per StateGroup (position m, angle rad, velocity m/s, rate rad/s)
  std::array<double, 4> bias{};
  std::uint32_t seed = 1;
  bool any() const;
};

class SensorNoise {
 public:
  /// `kinds` of the measured states. Throws std::invalid_argument for a negative level.
  SensorNoise(const NoiseSpec& spec, std::vector<StateKind> kinds);
  /// x (the measured state) + bias + white noise, in place.
  void apply(Eigen::VectorXd& x);
  const NoiseSpec& spec() const { return spec_; }

 private:
  NoiseSpec spec_;
  std::vector<StateKind> kinds_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace tmpc
