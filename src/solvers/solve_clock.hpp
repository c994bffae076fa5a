// Internal: the clock of the solvers' solve_us and time budgets (steady, microseconds).
#pragma once

#include <chrono>

namespace tmpc::detail {

inline double now_us() {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace tmpc::detail
