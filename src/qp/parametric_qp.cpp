#include "tmpc/qp/parametric_qp.hpp"

namespace tmpc {

ParametricQp ParametricQp::from_mpc(const MpcQpData& d) {
  ParametricQp p;
  const int nz = d.variables();
  const int nc = nz + d.N * d.n;
  p.H = d.H;
  p.F = d.F;
  p.f0 = Eigen::VectorXd::Zero(nz);
  p.A = Eigen::MatrixXd::Zero(nc, nz);
  p.A.topRows(nz).setIdentity();
  p.A.bottomRows(d.N * d.n) = d.P;
  p.E = Eigen::MatrixXd::Zero(nc, d.n);
  p.E.bottomRows(d.N * d.n) = d.Q;
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
