// Redundant rows by sequential LP elimination (see redundant_rows.hpp).
#include "tmpc/qp/redundant_rows.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "tmpc/sets/lp.hpp"

namespace tmpc {

bool ParameterDomain::contains(const Eigen::VectorXd& theta, double tol) const {
  if (theta.size() != D.cols()) return false;
  for (Eigen::Index i = 0; i < D.rows(); ++i) {
    const double v = D.row(i).dot(theta);
    if (!(v <= hi(i) + tol && v >= lo(i) - tol)) return false;
  }
  return true;
}

ParameterDomain mpc_parameter_domain(const MpcQpData& d, const Eigen::VectorXd& d_max, const Eigen::VectorXd& c_max) {
  const int n = d.n, nd = d.disturbances();
  ParameterDomain dom;
  if (nd == 0) {
    dom.D = Eigen::MatrixXd::Identity(n, d.parameters());  // v_prev (rate-weighted): free
    dom.lo = d.x_bar.lo;
    dom.hi = d.x_bar.hi;
    return dom;
  }
  if (d_max.size() != nd || c_max.size() != n || (d_max.array() < 0.0).any() || (c_max.array() < 0.0).any()) {
    throw std::invalid_argument("mpc_parameter_domain: the offset-free form needs d_max (" + std::to_string(nd) +
                                " entries >= 0) and c_max (" + std::to_string(n) + " entries >= 0), got " +
                                std::to_string(d_max.size()) + " and " + std::to_string(c_max.size()));
  }
  const int np = d.parameters();
  dom.D = Eigen::MatrixXd::Zero(n + nd + n, np);
  dom.D.block(0, 0, n, n).setIdentity();
  dom.D.block(0, n, n, nd) = d.Tx;
  dom.D.block(n, n, nd + n, nd + n).setIdentity();
  dom.lo.resize(n + nd + n);
  dom.hi.resize(n + nd + n);
  dom.lo << d.x_bar.lo, -d_max, -c_max;
  dom.hi << d.x_bar.hi, d_max, c_max;
  return dom;
}

RedundancyReport redundant_rows(const ParametricQp& qp, const ParameterDomain& domain, double tol) {
  RedundancyReport rep;
  if (qp.slacks > 0) return rep;
  const int nz = qp.nz(), np = qp.nx(), nc = qp.nc(), nd = static_cast<int>(domain.D.rows());
  if (domain.D.cols() != np || domain.lo.size() != nd || domain.hi.size() != nd) {
    throw std::invalid_argument("redundant_rows: the domain has " + std::to_string(domain.D.cols()) +
                                " columns for " + std::to_string(np) + " parameters");
  }
  // LP over x = (z, theta): rows 2i (upper side of row i), 2i + 1 (lower side), then
  // the domain's two sides per row.
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd G(2 * nc + 2 * nd, nz + np);
  Eigen::VectorXd b(2 * nc + 2 * nd);
  for (int i = 0; i < nc; ++i) {
    G.row(2 * i) << qp.A.row(i), qp.E.row(i);
    G.row(2 * i + 1) = -G.row(2 * i);
    b(2 * i) = std::isfinite(qp.hi0(i)) ? qp.hi0(i) : inf;
    b(2 * i + 1) = std::isfinite(qp.lo0(i)) ? -qp.lo0(i) : inf;
  }
  for (int i = 0; i < nd; ++i) {
    G.row(2 * nc + 2 * i) << Eigen::RowVectorXd::Zero(nz), domain.D.row(i);
    G.row(2 * nc + 2 * i + 1) = -G.row(2 * nc + 2 * i);
    b(2 * nc + 2 * i) = std::isfinite(domain.hi(i)) ? domain.hi(i) : inf;
    b(2 * nc + 2 * i + 1) = std::isfinite(domain.lo(i)) ? -domain.lo(i) : inf;
  }
  const Eigen::VectorXd free_lo = Eigen::VectorXd::Constant(nz + np, -inf), free_hi = -free_lo;
  {
    const LpResult feasible = solve_lp(Eigen::VectorXd::Zero(nz + np), G, b, Eigen::MatrixXd(0, nz + np),
                                       Eigen::VectorXd(0), free_lo, free_hi);
    if (feasible.status == LpStatus::Infeasible) {
      throw std::invalid_argument("redundant_rows: no (z, theta) satisfies the QP's rows over the domain");
    }
    if (feasible.status != LpStatus::Optimal) {
      rep.complete = false;
      return rep;
    }
  }
  LpWorkspace lp(G, b, free_lo, free_hi);
  // max s (a_i z + e_i theta) for the side s of row i, with that side's own row relaxed.
  auto implied = [&](int lp_row, double bound) {
    if (!std::isfinite(bound)) return true;  // no such side
    lp.set_rhs(lp_row, inf);
    const LpResult r = lp.minimize(-G.row(lp_row).transpose());
    ++rep.lps;
    if (r.status == LpStatus::Failed || r.status == LpStatus::Infeasible) rep.complete = false;
    return r.status == LpStatus::Optimal && -r.value <= bound + tol * (1.0 + std::abs(bound));
  };
  for (int i = 0; i < nc; ++i) {
    const bool upper = implied(2 * i, b(2 * i));
    const bool lower = upper && implied(2 * i + 1, b(2 * i + 1));
    if (upper && lower) {
      rep.rows.push_back(i);  // both sides stay relaxed: the row is gone
    } else {
      lp.set_rhs(2 * i, b(2 * i));
      lp.set_rhs(2 * i + 1, b(2 * i + 1));
    }
  }
  return rep;
}

}  // namespace tmpc

namespace tmpc {

RedundancyReport certify_redundant_rows(MpcQpData& d, const Eigen::VectorXd& d_max, const Eigen::VectorXd& c_max) {
  MpcQpData hard = d;
  hard.soft_penalty = 0.0;
  hard.redundant_rows.clear();
  hard.Sigma_delta.resize(0, 0);  // a row's redundancy does not depend on the cost (nor on v_prev)
  RedundancyReport rep = redundant_rows(ParametricQp::from_mpc(hard), mpc_parameter_domain(hard, d_max, c_max));
  d.redundant_rows = rep.rows;
  d.domain = mpc_parameter_domain(d, d_max, c_max);
  return rep;
}

}  // namespace tmpc
