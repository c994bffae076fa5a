// Internal: Nesterov's step-size sequence (4.31) with the residual restart of
// Algorithm 4.2, shared by both ADMM variants:
//   c < eta c_prev:  a+ = (1 + sqrt(1 + 4 a^2)) / 2, extrapolate with beta = (a - 1) / a+
//   otherwise:       a = 1, c_prev = c_prev / eta, restart from the previous iterate.
#pragma once

#include <cmath>

namespace tmpc::detail {

class NesterovRestart {
 public:
  void reset() {
    a_ = 1.0;
    c_prev_ = 1e300;
  }
  /// True (with the extrapolation weight) when the combined residual c fell enough;
  /// false means restart.
  bool accept(double c, double eta, double& beta) {
    if (c < eta * c_prev_) {
      const double a_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * a_ * a_));
      beta = (a_ - 1.0) / a_next;
      a_ = a_next;
      c_prev_ = c;
      return true;
    }
    a_ = 1.0;
    c_prev_ /= eta;
    beta = 0.0;
    return false;
  }

 private:
  double a_ = 1.0, c_prev_ = 1e300;
};

}  // namespace tmpc::detail
