// Multi-parametric QP (thesis 4.1, (4.1)-(4.13)) for the nominal MPC problem (4.7):
//   min_z 1/2 z'H z + (F th + f)'z   s.t.   G z <= w + S th,   th in Theta (a box),
// with H > 0. For an active set A with linearly independent rows G_A (LICQ), (4.9)-(4.12):
//   lambda_A(th) = -(G_A H^-1 G_A')^-1 (w_A + S_A th + G_A H^-1 (F th + f)),
//   z(th)        = -H^-1 (F th + f + G_A' lambda_A(th)),
// valid on the critical region CR_A = {th in Theta : G_N z(th) <= w_N + S_N th, lambda_A(th) >= 0}.
//
// The partition is built by geometric exploration (Tondel, Johansen and Bemporad 2003,
// facet stepping) with the neighbour's active set taken from an exact QP solve at the
// stepped point (robust to degeneracy where facet-to-facet inference is not), and a
// sampled coverage pass that seeds the exploration again wherever a feasible point is
// not covered. Degenerate cases: rows of G that vanish become parameter constraints,
// duplicate rows are merged, linearly dependent active sets are reduced to an
// independent subset, regions below the full dimension are not stored (their closures
// belong to full-dimensional neighbours), and a stepped point that lands on such a set is
// perturbed. Gives up, saying so, at a region or time limit.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/qp/parametric_qp.hpp"
#include "tmpc/sets/box.hpp"
#include "tmpc/sets/hpolytope.hpp"

namespace tmpc {

struct MpQp {
  Eigen::MatrixXd H, F, G, S;
  Eigen::VectorXd f, w;
  Box domain;                 ///< Theta
  Eigen::MatrixXd T;          ///< extra parameter constraints T th <= t (from rows of G that vanish)
  Eigen::VectorXd t;
  int nz() const { return static_cast<int>(H.rows()); }
  int ntheta() const { return static_cast<int>(F.cols()); }
  /// From lo0 - E th <= A z <= hi0 - E th (infinite bounds dropped), rows normalized,
  /// duplicates merged. Throws std::invalid_argument on inconsistent sizes or H not > 0.
  static MpQp from_parametric(const ParametricQp& qp, const Box& domain);
  /// The same QP as lo <= A z <= hi - E th with A = G, E = -S, no lower bounds (for
  /// the QP solvers, e.g. the reference oracle).
  ParametricQp as_parametric() const;
};

/// One critical region: th in {H th <= k} gives z(th) = Kz th + kz.
struct CriticalRegion {
  HPolytope set;              ///< normalized rows, redundant rows removed
  Eigen::MatrixXd Kz;
  Eigen::VectorXd kz;
  std::vector<int> active;    ///< rows of MpQp::G
  Eigen::VectorXd center;     ///< Chebyshev center
  double radius = 0.0;        ///< Chebyshev radius
  std::vector<char> boundary; ///< per row of set: 1 when it lies on Theta's boundary (no neighbour)
  Eigen::VectorXd z(const Eigen::VectorXd& th) const { return Kz * th + kz; }
};

struct MpQpOptions {
  int max_regions = 20000;
  double time_limit_s = 1800.0;
  double min_radius = 1e-6;   ///< Chebyshev radius below which a region counts as lower-dimensional
  double step = 1e-5;         ///< facet step (parameter units)
  int coverage_samples = 2000;///< per coverage pass
  int coverage_passes = 5;
  unsigned seed = 1;
};

struct MpQpStats {
  bool complete = false;      ///< exploration finished and the last coverage pass found no hole
  std::string stop_reason;    ///< why it is not complete
  double seconds = 0.0;
  int qp_solves = 0, lps = 0;
  int lower_dimensional = 0;  ///< active sets whose region was lower-dimensional (skipped)
  int licq_reduced = 0;       ///< active sets reduced to an independent subset
  int perturbed = 0;          ///< stepped points moved off a degenerate set
  int unresolved_facets = 0;  ///< facets whose neighbour could not be identified
  int holes_found = 0;        ///< uncovered feasible samples that seeded new regions
  int coverage_checked = 0;   ///< feasible samples located in the final pass
};

struct Partition {
  std::vector<CriticalRegion> regions;
  Box domain;
  MpQpStats stats;
  /// Lowest-index region containing th (tolerance tol), or -1.
  int locate(const Eigen::VectorXd& th, double tol = 1e-9) const;
};

Partition solve_mpqp(const MpQp& p, const MpQpOptions& opt = {});

/// True when some z satisfies G z <= w + S th (an LP), i.e. th is in the feasible set.
bool mpqp_feasible(const MpQp& p, const Eigen::VectorXd& th);

}  // namespace tmpc
