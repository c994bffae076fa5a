// Nesterov's step-size sequence (4.31) with the residual restart of Algorithm 4.2,
// shared by the CPU ADMM solvers (double) and the GPU kernel (float):
//   c < eta c_prev:  a+ = (1 + sqrt(1 + 4 a^2)) / 2, extrapolate with beta = (a - 1) / a+
//   otherwise:       a = 1, c_prev = c_prev / eta, restart from the previous iterate.
// C++14 and no library headers beyond <math.h>, so nvcc of every JetPack compiles it.
#pragma once

#include <math.h>  // sqrtf, sqrt on the host (built into device code)

#ifndef TMPC_TEAM_FN
#if defined(__CUDACC__)
#define TMPC_TEAM_FN __device__ __forceinline__
#else
#define TMPC_TEAM_FN inline
#endif
#endif

namespace tmpc {
namespace gpu {
namespace detail {

TMPC_TEAM_FN float sqrt_of(float v) { return sqrtf(v); }
TMPC_TEAM_FN double sqrt_of(double v) { return sqrt(v); }
/// A start value of c_prev above any residual measure.
TMPC_TEAM_FN float huge_of(float) { return 3.0e38f; }
TMPC_TEAM_FN double huge_of(double) { return 1e300; }

}  // namespace detail

template <class R>
struct NesterovRestart {
  R a = 1, c_prev = detail::huge_of(R(0));
  /// True (with the extrapolation weight) when the combined residual c fell enough;
  /// false means restart.
  TMPC_TEAM_FN bool accept(R c, R eta, R& beta) {
    if (c < eta * c_prev) {
      const R a_next = R(0.5) * (R(1) + detail::sqrt_of(R(1) + R(4) * a * a));
      beta = (a - R(1)) / a_next;
      a = a_next;
      c_prev = c;
      return true;
    }
    a = 1;
    c_prev /= eta;
    beta = 0;
    return false;
  }
};

}  // namespace gpu
}  // namespace tmpc
