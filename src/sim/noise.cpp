// Sensor noise (see noise.hpp).
#include "tmpc/sim/noise.hpp"

#include <cmath>
#include <stdexcept>

namespace tmpc {

bool NoiseSpec::any() const {
  for (int g = 0; g < 4; ++g) {
    if (white[static_cast<std::size_t>(g)] != 0.0 || bias[static_cast<std::size_t>(g)] != 0.0) return true;
  }
  return false;
}

SensorNoise::SensorNoise(const NoiseSpec& spec, std::vector<StateKind> kinds)
    : spec_(spec), kinds_(std::move(kinds)), rng_(spec.seed) {
  for (double w : spec_.white) {
    if (!(w >= 0.0) || !std::isfinite(w)) throw std::invalid_argument("sensor noise: white levels must be >= 0");
  }
}

void SensorNoise::apply(Eigen::VectorXd& x) {
  for (Eigen::Index i = 0; i < x.size() && i < static_cast<Eigen::Index>(kinds_.size()); ++i) {
    const StateGroup g = group_of(kinds_[static_cast<std::size_t>(i)]);
    if (g == StateGroup::None) continue;
    const auto k = static_cast<std::size_t>(g);
    x(i) += spec_.bias[k] + spec_.white[k] * normal_(rng_);
  }
}

}  // namespace tmpc
