// Critical region of one active set (thesis (4.9)-(4.13)) with redundant rows removed.
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "tmpc/sets/lp.hpp"
#include "tmpc/explicit/mpqp.hpp"

namespace tmpc::detail {

enum class RegionOutcome { Ok, Licq, Empty, LowerDimensional };

struct RegionBuild {
  RegionOutcome outcome = RegionOutcome::Empty;
  CriticalRegion region;
  int lps = 0;
};

/// Precomputed once per problem.
struct MpQpFactors {
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::MatrixXd HinvGt;  ///< H^-1 G'
  Eigen::MatrixXd HinvF;   ///< H^-1 F
  Eigen::VectorXd Hinvf;   ///< H^-1 f
  explicit MpQpFactors(const MpQp& p);
};

RegionBuild build_region(const MpQp& p, const MpQpFactors& fac, const std::vector<int>& active, double min_radius);

/// Rows of (A, b) (normalized) after dropping those redundant in {A x <= b}. The rows
/// flagged in box_row describe `box`; other rows the box alone satisfies are dropped
/// without an LP. Returns the kept row indices. `lps` counts the LPs solved.
std::vector<int> irredundant_rows(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                                  const std::vector<char>& box_row, int& lps);

/// Chebyshev center of facet i of {A x <= b} within the box (rows normalized): radius < 0 if none.
ChebyshevBall facet_ball(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int i, const Box& box);

}  // namespace tmpc::detail
