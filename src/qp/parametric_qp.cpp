#include "tmpc/qp/parametric_qp.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tmpc {

ParametricQp ParametricQp::from_mpc(const MpcQpData& d) {
  ParametricQp p;
  const int nz = d.variables();
  const int nc = nz + d.N * d.n;
  const int nd = d.disturbances(), np = d.parameters();
  if (d.Tu.cols() != nd || (nd > 0 && (d.Tx.rows() != d.n || d.Tu.rows() != d.m || d.Phi.rows() != d.N * d.n ||
                                       d.Phi.cols() != d.n))) {
    throw std::invalid_argument("ParametricQp::from_mpc: offset-free data Tx (" + std::to_string(d.Tx.rows()) + "x" +
                                std::to_string(d.Tx.cols()) + "), Tu (" + std::to_string(d.Tu.rows()) + "x" +
                                std::to_string(d.Tu.cols()) + "), Phi (" + std::to_string(d.Phi.rows()) + "x" +
                                std::to_string(d.Phi.cols()) + ") disagree with n = " + std::to_string(d.n) +
                                ", m = " + std::to_string(d.m) + ", N = " + std::to_string(d.N));
  }
  p.H = d.H;
  p.F = Eigen::MatrixXd::Zero(nz, np);
  p.F.leftCols(d.n) = d.F;
  if (nd > 0) p.F.middleCols(d.n + nd, d.n) = 2.0 * d.P.transpose() * d.Wx() * d.Phi;
  if (d.rate_weighted()) p.F.block(0, d.rate_parameter(), d.m, d.m) = -2.0 * d.Sigma_delta;  // u(0) - v_prev
  p.f0 = Eigen::VectorXd::Zero(nz);
  p.A = Eigen::MatrixXd::Zero(nc, nz);
  p.A.topRows(nz).setIdentity();
  p.A.bottomRows(d.N * d.n) = d.P;
  p.E = Eigen::MatrixXd::Zero(nc, np);
  p.E.block(nz, 0, d.N * d.n, d.n) = d.Q;
  if (nd > 0) {
    // The sets around the steady state (lo - u_s or x_s per stage), and the offset c.
    for (int i = 0; i < d.M; ++i) p.E.block(i * d.m, d.n, d.m, nd) = d.Tu;
    for (int i = 0; i < d.N; ++i) p.E.block(nz + i * d.n, d.n, d.n, nd) = d.Tx;
    p.E.block(nz, d.n + nd, d.N * d.n, d.n) = d.Phi;
  }
  p.lo0.resize(nc);
  p.hi0.resize(nc);
  for (int i = 0; i < d.M; ++i) {
    p.lo0.segment(i * d.m, d.m) = d.u_bar.lo;
    p.hi0.segment(i * d.m, d.m) = d.u_bar.hi;
  }
  for (int i = 0; i < d.N; ++i) {
    p.lo0.segment(nz + i * d.n, d.n) = d.x_bar.lo;
    p.hi0.segment(nz + i * d.n, d.n) = d.x_bar.hi;
  }
  return d.soft() ? soften(p, d.N, d.n, d.soft_penalty) : p;
}

ParametricQp ParametricQp::soften(const ParametricQp& hard, int N, int n, double penalty) {
  if (!(penalty > 0.0 && std::isfinite(penalty))) {
    throw std::invalid_argument("ParametricQp::soften: the penalty must be positive and finite, got " + std::to_string(penalty));
  }
  if (hard.slacks != 0 || N < 1 || n < 1 || hard.nc() < N * n) {
    throw std::invalid_argument("ParametricQp::soften: needs a hard QP whose last N n rows are the state constraints");
  }
  const int nu = hard.nz(), nin = hard.nc() - N * n, ns = n, rows = N * n;
  const double inf = std::numeric_limits<double>::infinity();
  ParametricQp p;
  p.slacks = ns;
  const int nz = nu + ns, nc = nin + 2 * rows + ns;
  p.H = Eigen::MatrixXd::Zero(nz, nz);
  p.H.topLeftCorner(nu, nu) = hard.H;
  p.H.bottomRightCorner(ns, ns).diagonal().setConstant(kSlackCurvature * hard.H.diagonal().maxCoeff());
  p.F = Eigen::MatrixXd::Zero(nz, hard.nx());
  p.F.topRows(nu) = hard.F;
  p.f0 = Eigen::VectorXd::Zero(nz);
  p.f0.head(nu) = hard.f0;
  p.f0.tail(ns).setConstant(penalty);
  p.A = Eigen::MatrixXd::Zero(nc, nz);
  p.E = Eigen::MatrixXd::Zero(nc, hard.nx());
  p.lo0.resize(nc);
  p.hi0.resize(nc);
  // Inputs, unchanged.
  p.A.topLeftCorner(nin, nu) = hard.A.topRows(nin);
  p.E.topRows(nin) = hard.E.topRows(nin);
  p.lo0.head(nin) = hard.lo0.head(nin);
  p.hi0.head(nin) = hard.hi0.head(nin);
  // x - s <= hi (upper rows), x + s >= lo (lower rows); stage k, state i uses s_i.
  const Eigen::MatrixXd Ax = hard.A.bottomRows(rows), Ex = hard.E.bottomRows(rows);
  p.A.block(nin, 0, rows, nu) = Ax;
  p.A.block(nin + rows, 0, rows, nu) = Ax;
  p.E.middleRows(nin, rows) = Ex;
  p.E.middleRows(nin + rows, rows) = Ex;
  for (int k = 0; k < N; ++k) {
    for (int i = 0; i < n; ++i) {
      p.A(nin + k * n + i, nu + i) = -1.0;
      p.A(nin + rows + k * n + i, nu + i) = 1.0;
    }
  }
  p.lo0.segment(nin, rows).setConstant(-inf);
  p.hi0.segment(nin, rows) = hard.hi0.tail(rows);
  p.lo0.segment(nin + rows, rows) = hard.lo0.tail(rows);
  p.hi0.segment(nin + rows, rows).setConstant(inf);
  // s >= 0.
  p.A.bottomRightCorner(ns, ns).setIdentity();
  p.lo0.tail(ns).setZero();
  p.hi0.tail(ns).setConstant(inf);
  return p;
}

void ParametricQp::instance_into(const Eigen::VectorXd& x0, Eigen::VectorXd& f, Eigen::VectorXd& lo,
                                 Eigen::VectorXd& hi) const {
  f = f0;
  f.noalias() += F * x0;
  lo = lo0;
  lo.noalias() -= E * x0;
  hi = hi0;
  hi.noalias() -= E * x0;
}

CondensedQp ParametricQp::instance(const Eigen::VectorXd& x0) const {
  CondensedQp q;
  q.H = H;
  q.A = A;
  q.f.resize(nz());
  q.lo.resize(nc());
  q.hi.resize(nc());
  instance_into(x0, q.f, q.lo, q.hi);
  return q;
}

}  // namespace tmpc
