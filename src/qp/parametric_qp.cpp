#include "tmpc/qp/parametric_qp.hpp"

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
  if (nd > 0) p.F.rightCols(d.n) = 2.0 * d.P.transpose() * d.Wx() * d.Phi;
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
