// Shared fixtures of the model tests: the default config and random admissible states.
#pragma once

#include <cmath>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>

#include "tmpc/model/config.hpp"
#include "tmpc/model/dynamics.hpp"
#include "tmpc/model/trajectory.hpp"

namespace tmpc::test {

/// The source tree: $TMPC_SOURCE_DIR when set (test binaries run from a copy of the
/// tree elsewhere, e.g. on a GPU machine), else where this build's sources were.
inline std::string source_dir() {
  const char* env = std::getenv("TMPC_SOURCE_DIR");
  return env != nullptr && env[0] != '\0' ? std::string(env) : std::string(TMPC_SOURCE_DIR);
}

/// Under ASan (-DTMPC_SANITIZE=ON, the CI's asan variant) a sampled check runs a tenth
/// of its samples: the sanitizer checks memory on every path the samples take, and the
/// default build checks the statistics at full size.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
inline int sample_count(int n) { return kSanitized ? (n + 9) / 10 : n; }

inline const Config& default_config() {
  static const Config cfg = load_config(source_dir() + "/config/tiltrotor.yaml");
  return cfg;
}

/// The thesis' helix (6.2; config/scenarios/thesis_helix.yaml): r = 5 m, z = 4 - 3 cos(w t),
/// w = pi / 40 rad/s, yaw 0.
inline std::shared_ptr<const Trajectory> thesis_helix() {
  static const std::shared_ptr<const Trajectory> h = make_helix({Eigen::Vector3d(0, 0, 4), 5.0, 3.0, M_PI / 40.0, 0.0});
  return h;
}

/// Random admissible configuration: position anywhere, attitude and joint angles
/// inside +-0.5 rad (the state box), yaw free.
inline Vec10 random_q(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(-5.0, 5.0), ang(-0.5, 0.5), yaw(-3.1, 3.1);
  Vec10 q;
  q << pos(rng), pos(rng), pos(rng), ang(rng), ang(rng), yaw(rng), ang(rng), ang(rng), ang(rng), ang(rng);
  return q;
}

/// Random velocities inside the velocity box of the case study.
inline Vec10 random_qd(std::mt19937_64& rng) {
  const double box[10] = {0.6, 1.0, 0.2, 1.0, 1.0, 0.5, 2.0, 1.0, 0.2, 0.2};
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec10 qd;
  for (int i = 0; i < 10; ++i) qd(i) = box[i] * u(rng);
  return qd;
}

inline Eigen::Vector4d random_u(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> f(0.0, 30.0), tau(-2.0, 2.0);
  return {f(rng), f(rng), tau(rng), tau(rng)};
}

}  // namespace tmpc::test
