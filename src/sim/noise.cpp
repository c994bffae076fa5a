// Sensor noise (see noise.hpp).
#include "tmpc/sim/noise.hpp"

#include <cmath>
#include <stdexcept>

namespace tmpc {

bool NoiseSpec::any() const {
  for (int g = 0; g < 4; ++g) {
    const auto k = static_cast<std::size_t>(g);
    if (white[k] != 0.0 || bias[k] != 0.0 || (outlier[k] != 0.0 && outlier_probability[k] > 0.0)) return true;
  }
  return false;
}

SensorNoise::SensorNoise(const NoiseSpec& spec, std::vector<StateKind> kinds)
    : spec_(spec), kinds_(std::move(kinds)), rng_(spec.seed), glitch_rng_(spec.seed ^ 0x9e3779b97f4a7c15ULL) {
  for (std::size_t k = 0; k < 4; ++k) {
    if (!(spec_.white[k] >= 0.0) || !std::isfinite(spec_.white[k])) {
      throw std::invalid_argument("sensor noise: white levels must be >= 0");
    }
    if (!(spec_.outlier[k] >= 0.0) || !std::isfinite(spec_.outlier[k])) {
      throw std::invalid_argument("sensor noise: outlier sizes must be >= 0");
    }
    if (!(spec_.outlier_probability[k] >= 0.0 && spec_.outlier_probability[k] <= 1.0)) {
      throw std::invalid_argument("sensor noise: outlier probabilities must lie in [0, 1]");
    }
  }
}

void SensorNoise::apply(Eigen::VectorXd& x) {
  for (Eigen::Index i = 0; i < x.size() && i < static_cast<Eigen::Index>(kinds_.size()); ++i) {
    const StateGroup g = group_of(kinds_[static_cast<std::size_t>(i)]);
    if (g == StateGroup::None) continue;
    const auto k = static_cast<std::size_t>(g);
    x(i) += spec_.bias[k] + spec_.white[k] * normal_(rng_);
    if (spec_.outlier[k] > 0.0 && spec_.outlier_probability[k] > 0.0 &&
        uniform_(glitch_rng_) < spec_.outlier_probability[k]) {
      x(i) += uniform_(glitch_rng_) < 0.5 ? -spec_.outlier[k] : spec_.outlier[k];
      ++glitches_;
    }
  }
}

}  // namespace tmpc
