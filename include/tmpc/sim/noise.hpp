// Sensor noise of a scenario: per state group (positions, angles with the yaw,
// velocities, angular rates) a white Gaussian part of standard deviation `white` and a
// constant `bias`, from a seeded generator; added to the measured state the controller
// is sent, never to the plant. Glitches (a GNSS multipath jump, a vibration spike): each
// sample of a group's rows is, with probability `outlier_probability`, off by
// +-`outlier` (the sign drawn), from a second generator, so that a scenario's white
// noise does not change when glitches are added. apply() allocates nothing.
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
  std::array<double, 4> outlier{};              ///< glitch size per group (same units)
  std::array<double, 4> outlier_probability{};  ///< per sample and row, in [0, 1]
  std::uint32_t seed = 1;
  bool any() const;
};

class SensorNoise {
 public:
  /// `kinds` of the measured states. Throws std::invalid_argument for a negative level
  /// or glitch size, or a glitch probability outside [0, 1].
  SensorNoise(const NoiseSpec& spec, std::vector<StateKind> kinds);
  /// x (the measured state) + bias + white noise, in place.
  void apply(Eigen::VectorXd& x);
  const NoiseSpec& spec() const { return spec_; }
  /// Samples glitched so far.
  long glitches() const { return glitches_; }

 private:
  NoiseSpec spec_;
  std::vector<StateKind> kinds_;
  std::mt19937_64 rng_, glitch_rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  long glitches_ = 0;
};

}  // namespace tmpc
