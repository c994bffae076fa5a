// Rows of the parametric QP that never bind (design time, LP-certified):
//   row i of  lo0 <= A z + E theta <= hi0  is redundant over the parameter domain
//   Theta = {theta : dlo <= D theta <= dhi}  when both its sides hold at every (z, theta)
//   that satisfies the other kept rows with theta in Theta:
//     max {+-(a_i z + e_i theta)} over that polyhedron  <=  +-bound_i + tol (1 + |bound_i|).
// Rows are tested one at a time against the rows kept so far (sequential elimination:
// of two copies of one row, one stays), so the kept rows describe the same feasible set
// for every theta in Theta and dropping the others changes no solution there. Outside
// Theta the certificate says nothing: a solver using it checks theta first. Cost: about
// 600 warm-started LPs (3 s) for the case study's 496 rows (a row's upper side that
// binds skips its lower side's LP).
// In the thesis' QP the state rows implied by the input box and the previous stage's
// state box drop (x(k+1) = A x(k) + B u(k), (3.53)); the domain is x0 in X_bar.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/qp/parametric_qp.hpp"

namespace tmpc {

/// The domain of the MPC data's parameter: the nominal state x0 in X_bar; in the
/// offset-free form (parameter (x0 - x_s, d, c)) x0 = (x0 - x_s) + Tx d in X_bar and
/// |d_j| <= d_max(j), |c_i| <= c_max(i) (the estimates the certificate covers).
ParameterDomain mpc_parameter_domain(const MpcQpData& d, const Eigen::VectorXd& d_max = {},
                                     const Eigen::VectorXd& c_max = {});

struct RedundancyReport {
  std::vector<int> rows;  ///< redundant rows, ascending
  int lps = 0;            ///< LPs solved
  bool complete = true;   ///< false when an LP failed (the rows found before are kept)
};

/// The redundant rows of the hard QP over the domain (a softened QP: none). Throws
/// std::invalid_argument for sizes that do not match or an empty feasible set.
RedundancyReport redundant_rows(const ParametricQp& qp, const ParameterDomain& domain, double tol = 1e-9);

/// Certifies the MPC data's redundant rows over mpc_parameter_domain(d, d_max, c_max)
/// and records them and the domain in d (what the artifact stores); returns the report.
RedundancyReport certify_redundant_rows(MpcQpData& d, const Eigen::VectorXd& d_max = {},
                                        const Eigen::VectorXd& c_max = {});

}  // namespace tmpc
