// The nominal QP of the tube MPC in the flat float form the GPU solver keeps resident
// on the device (DESIGN.md section 5, GPU). C++14 and no Eigen: this header is
// compiled by nvcc (JetPack 4's nvcc 10.2 has no C++17) as well as by the host build.
//
// exact variant (E3), polytope formulation (thesis (4.7)), z = u_hat:
//   min 1/2 z'Hz + f'z,  f = f0 + F x0,   lo0 - E x0 <= A z <= hi0 - E x0
//   x-step with Kinv = (H + sigma I + A' R A)^-1, R = diag(rho_vec) (fixed penalty)
// thesis variant, Algorithm 4.3 (4.25)-(4.28), x_hat = P u_hat + Q x0:
//   u = clip(rho H1inv P'(x^ - Q x0 + lam^)),  H1 = rho P'P + 2 W_u
//   x = clip(H2inv rho (P u + Q x0 - lam)),    H2 = rho I + 2 W_x (diagonal stages, dense last)
#pragma once

#include <vector>

namespace tmpc {
namespace gpu {

enum Variant : int { kExact = 0, kThesis = 1 };

/// Device status codes; the same values as tmpc::SolveStatus.
enum Status : int {
  kConverged = 0,
  kMaxIterations = 1,
  kTimeBudget = 2,
  kNumericalFailure = 3,
  kInvalidInput = 4,
  kInfeasible = 5,
};

struct AdmmSettings {
  int variant = kExact;
  float eps_abs = 1e-3f, eps_rel = 1e-3f;
  int max_iterations = 4000;
  int check_every = 5;         ///< exact variant: termination test every k iterations
  float r = 0.5f, s = 1.0f;    ///< symmetric dual steps (4.21), (4.23)
  int nesterov = 0;            ///< exact variant: extrapolation (4.29)-(4.31) (thesis: always)
  float eta = 0.999f;          ///< restart factor of Algorithm 4.2
  float sigma = 1e-6f;         ///< proximal term on z (exact)
  float eps_pinf = 1e-4f;      ///< exact: primal infeasibility certificate tolerance (0: off)
  int warm_start = 1;          ///< shift the previous solution one step
  long long time_budget_ns = 0;  ///< 0: none; checked inside the iteration loop
};

/// Flat row-major data of one controller's QP (float on the device; double for the
/// host checks of the kernel code).
template <class R>
struct BasicAdmmProblem {
  int nz = 0, nc = 0, nx = 0;  ///< variables, constraint rows, parameter (state) size
  int m = 0, M = 0;            ///< inputs per step, control horizon (nz = M m)
  int n = 0, N = 0;            ///< states per step, prediction horizon (nc = nz + N n)
  R rho = 0;                   ///< exact variant's penalty (set-up spectral rule)
  R rho_thesis = 0;            ///< thesis variant's penalty
  // exact
  std::vector<R> H, f0, F, A, E, lo0, hi0, rho_vec, Kinv;
  // thesis
  std::vector<R> P, Q, H1inv, H2diag, H2last, xlo, xhi, ulo, uhi;
  // Optional block form of P (and A = [I; P]): G_l = A^l B, S_l = G_0 + ... + G_l,
  // l = 0..N-1, n x m row-major each (tmpc/gpu/admm_kernel.hpp, MatView)
  std::vector<R> Gblk, Sblk;

  /// Empty string when sizes agree, else what is wrong.
  const char* check() const {
    if (nz <= 0 || nc <= 0 || nx <= 0) return "empty problem";
    if (nz != M * m || nc != nz + N * n) return "nz != M m or nc != nz + N n";
    const std::size_t z = static_cast<std::size_t>(nz), c = static_cast<std::size_t>(nc),
                      x = static_cast<std::size_t>(nx), s = static_cast<std::size_t>(N) * n;
    if (H.size() != z * z || f0.size() != z || F.size() != z * x || A.size() != c * z || E.size() != c * x ||
        lo0.size() != c || hi0.size() != c || rho_vec.size() != c || Kinv.size() != z * z)
      return "exact-variant arrays have the wrong sizes";
    if (P.size() != s * z || Q.size() != s * x || H1inv.size() != z * z ||
        H2diag.size() != static_cast<std::size_t>(n) || H2last.size() != static_cast<std::size_t>(n) * n ||
        xlo.size() != s || xhi.size() != s || ulo.size() != z || uhi.size() != z)
      return "thesis-variant arrays have the wrong sizes";
    const std::size_t blocks = static_cast<std::size_t>(N) * n * m;
    if (!Gblk.empty() && (Gblk.size() != blocks || Sblk.size() != blocks)) return "block form has the wrong sizes";
    return "";
  }
};

using AdmmProblem = BasicAdmmProblem<float>;

/// What comes back per solve (u_bar(0) and the status; the full z on request).
struct AdmmOutcome {
  int status = kNumericalFailure;
  int iterations = 0;
  int restarts = 0;
  float primal_residual = 0.0f, dual_residual = 0.0f;
};

}  // namespace gpu
}  // namespace tmpc
