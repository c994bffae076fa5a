// Percentiles of timing samples (wake-up latencies, solve times), after a run: the
// sample at index floor(p n) of the sorted samples (the largest for p = 1).
#pragma once

#include <algorithm>
#include <vector>

namespace tmpc {

/// Sorts `v` in place; 0 for no samples.
inline double percentile(std::vector<double>& v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

}  // namespace tmpc
