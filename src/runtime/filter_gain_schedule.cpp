// Noise-adaptive filter gains (see filter_gain_schedule.hpp).
#include "tmpc/runtime/filter_gain_schedule.hpp"

#include <cmath>

namespace tmpc {

const std::vector<double>& FilterGainSchedule::scales() {
  static const std::vector<double> s{1.0, 2.0, 4.0, 8.0};
  return s;
}

FilterGainSchedule::FilterGainSchedule(const KalmanDesign& k) {
  for (double s : scales()) {
    designs_.push_back(s == 1.0 ? k : redesign_kalman(k, k.Q, (s * s) * k.R));
    sds_.push_back(tmpc::innovation_sd(designs_.back()));
  }
}

const Eigen::MatrixXd& FilterGainSchedule::update(double level) {
  const std::vector<double>& s = scales();
  const int last = static_cast<int>(s.size()) - 1;
  auto edge = [&](int j) { return std::sqrt(s[static_cast<std::size_t>(j)] * s[static_cast<std::size_t>(j + 1)]); };
  while (index_ < last && level > edge(index_) * (1.0 + kHysteresis)) ++index_;
  while (index_ > 0 && level < edge(index_ - 1) / (1.0 + kHysteresis)) --index_;
  return gain();
}

}  // namespace tmpc
