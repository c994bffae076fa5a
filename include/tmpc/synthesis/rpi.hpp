// Robust positively invariant (RPI) zonotopes for the error dynamics e+ = S e + w.
//
// LTI, thesis (3.36)-(3.37) (Limon et al. 2008, Rakovic et al. 2005):
//   Z = (1 - alpha(j))^-1 H_z(j) B + (I - S)^-1 w0,  H_z(j) = [S^(j-1) H_w ... H_w]
//   j = smallest with alpha(j) <= lambda / (lambda + 1), alpha(j) = min a : S^j W0 <= a W0.
// alpha(j) comes from W0's support function over its facets (exact for a box or any
// parallelotope: alpha = ||H_w^-1 S^j H_w||_inf). A W0 with more generators than
// dimensions is replaced by its interval hull (the thesis' box form, conservative).
//
// LPV, two variants:
//   thesis (Theorem 3.3 literally): S_z = S_0 + sum_i (S_i - S_0), then the LTI formula.
//     It does not bound the LPV realizations (E6); kept for comparison.
//   robust (default): invariant for every vertex S_i. The vertex deviation is treated as
//     extra disturbance: W_a = W + box(union_i (S_i - S_0) Z), Z = RPI(S_0, W_a), iterated
//     to a fixed point and closed by a final inflation and check. Then
//     S_i Z + W = S_0 Z + (S_i - S_0) Z + W <= S_0 Z + W_a <= Z for every i.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/sets/zonotope.hpp"

namespace tmpc {

struct RpiSettings {
  double lambda = 0.05;   ///< relative error bound of (3.34)
  int max_j = 50000;      ///< cap on j: beyond it the computation is refused, not truncated
  int max_lpv_iterations = 50;
};

struct RpiResult {
  Zonotope Z;
  int j = 0;
  double alpha = 0.0;
  std::string method;                 ///< "lti", "lpv-thesis", "lpv-robust"
  bool w_box_hull = false;            ///< W0 was replaced by its interval hull
  int lpv_iterations = 0;             ///< robust variant
  Eigen::VectorXd lpv_inflation;      ///< half-widths of box(union (S_i - S_0) Z) used
};

/// LTI zonotope of (3.36). Throws std::runtime_error if S is not stable or j would exceed max_j.
RpiResult rpi_lti(const Eigen::MatrixXd& S, const Zonotope& W, const RpiSettings& s);

/// Thesis Theorem 3.3 literally: S_z = S_0 + sum_i (S_i - S_0).
RpiResult rpi_lpv_thesis(const Eigen::MatrixXd& S0, const std::vector<Eigen::MatrixXd>& S_vertices, const Zonotope& W,
                         const RpiSettings& s);

/// Invariant for every vertex (see above). W must be a box or parallelotope.
RpiResult rpi_lpv_robust(const Eigen::MatrixXd& S0, const std::vector<Eigen::MatrixXd>& S_vertices, const Zonotope& W,
                         const RpiSettings& s);

/// Independent invariance check by support functions: the largest ratio
/// h_{S_i Z + W}(d) / h_Z(d) over `directions` random unit directions plus the
/// coordinate axes, for every S_i (<= 1 means invariant in those directions).
struct SupportCheck {
  double worst_ratio = 0.0;
  int worst_vertex = -1;
  int directions = 0;
};
SupportCheck check_invariance_support(const Zonotope& Z, const std::vector<Eigen::MatrixXd>& S, const Zonotope& W,
                                      int directions, unsigned seed);

/// Simulated error trajectories from e = 0 under random w in W (uniform over the
/// generators' box, with vertices of W mixed in) and random vertex switching.
/// Membership in Z is tested on the half-spaces {d'e <= h_Z(d)} of the given
/// directions (the axes and `directions` random ones): an outer description of Z.
struct SimulationCheck {
  long exits = 0;            ///< steps at which a half-space was violated
  double worst_ratio = 0.0;  ///< max over steps and directions of d'e / h_Z(d)
  int trajectories = 0;
  int steps = 0;
};
SimulationCheck check_invariance_simulation(const Zonotope& Z, const std::vector<Eigen::MatrixXd>& S, const Zonotope& W,
                                            int trajectories, int steps, int directions, unsigned seed);

}  // namespace tmpc
