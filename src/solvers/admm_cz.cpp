// "cz": the nominal problem in constrained-zonotope coordinates (4.35)-(4.47).
#include "solvers_internal.hpp"
#include "tmpc/sets/constrained_zonotope.hpp"

namespace tmpc::detail {

AdmmCz::AdmmCz(const MpcQpData& d, const ParametricQp& polytope, const SolverOptions& opt)
    : polytope_(polytope), opt_(opt) {
  const ConstrainedZonotope U = ConstrainedZonotope::from_box(d.u_bar);
  const ConstrainedZonotope X = ConstrainedZonotope::from_box(d.x_bar);
  const int gu = U.generators(), gx = X.generators(), cu = U.constraints(), cx = X.constraints();
  const int M = d.M, N = d.N, n = d.n, m = d.m;
  const int nzu = M * gu, nzx = N * gx, nzeta = nzu + nzx;
  // Block-diagonal stacks (4.38)-(4.42).
  Gu_full_ = Eigen::MatrixXd::Zero(M * m, nzu);
  cu_full_.resize(M * m);
  for (int i = 0; i < M; ++i) {
    Gu_full_.block(i * m, i * gu, m, gu) = U.G;
    cu_full_.segment(i * m, m) = U.c;
  }
  Eigen::MatrixXd Gx_full = Eigen::MatrixXd::Zero(N * n, nzx);
  Eigen::VectorXd cx_full(N * n);
  for (int i = 0; i < N; ++i) {
    Gx_full.block(i * n, i * gx, n, gx) = X.G;
    cx_full.segment(i * n, n) = X.c;
  }
  // Cost (4.43): f1 + f2 with the x0-free linear term 2 [Gu'W_u c_u; Gx'W_x c_x].
  const Eigen::MatrixXd Wx = d.Wx(), Wu = d.Wu();
  cz_.H = Eigen::MatrixXd::Zero(nzeta, nzeta);
  cz_.H.topLeftCorner(nzu, nzu) = 2.0 * Gu_full_.transpose() * Wu * Gu_full_;
  cz_.H.bottomRightCorner(nzx, nzx) = 2.0 * Gx_full.transpose() * Wx * Gx_full;
  cz_.f0.resize(nzeta);
  cz_.f0 << 2.0 * Gu_full_.transpose() * Wu * cu_full_, 2.0 * Gx_full.transpose() * Wx * cx_full;
  // Offset-free form (mpc_qp.hpp): the sets hold the nominal u_hat = c_u + G_u zeta_u and
  // x_hat = c_x + G_x zeta_x, the cost and the dynamics act on u_hat - U_s and
    // x_hat - X_s (U_s, X_s: the stacked targets of d), which moves the linear term by
  // -2 [G_u'W_u U_s; G_x'W_x X_s] and the dynamics right-hand side by X_s - P U_s + Phi c.
  const int nd = d.disturbances();
  const int np = d.parameters();
  cz_.F = Eigen::MatrixXd::Zero(nzeta, np);
  // Rows: dynamics (4.44), the sets' equalities (4.39), (4.42), unit boxes (4.45).
  const int rows = N * n + M * cu + N * cx + nzeta;
  cz_.A = Eigen::MatrixXd::Zero(rows, nzeta);
  cz_.E = Eigen::MatrixXd::Zero(rows, np);
  cz_.lo0.resize(rows);
  cz_.hi0.resize(rows);
  cz_.A.block(0, 0, N * n, nzu) = -d.P * Gu_full_;
  cz_.A.block(0, nzu, N * n, nzx) = Gx_full;
  cz_.lo0.head(N * n) = d.P * cu_full_ - cx_full;  // + Q x0 through E = -Q
  cz_.hi0.head(N * n) = cz_.lo0.head(N * n);
  cz_.E.block(0, 0, N * n, n) = -d.Q;
  if (nd > 0) {
    Eigen::MatrixXd Us(M * m, nd), Xs(N * n, nd);
    for (int i = 0; i < M; ++i) Us.middleRows(i * m, m) = d.Tu;
    for (int i = 0; i < N; ++i) Xs.middleRows(i * n, n) = d.Tx;
    cz_.E.block(0, n, N * n, nd) = d.P * Us - Xs;  // lo = lo0 - E x0
    cz_.E.block(0, n + nd, N * n, n) = -d.Phi;      // x_hat picks up Phi c
    cz_.F.block(0, n, nzu, nd) = -2.0 * Gu_full_.transpose() * Wu * Us;
    cz_.F.block(nzu, n, nzx, nd) = -2.0 * Gx_full.transpose() * Wx * Xs;
  }
  int r = N * n;
  for (int i = 0; i < M; ++i, r += cu) {
    cz_.A.block(r, i * gu, cu, gu) = U.A;
    cz_.lo0.segment(r, cu) = U.b;
    cz_.hi0.segment(r, cu) = U.b;
  }
  for (int i = 0; i < N; ++i, r += cx) {
    cz_.A.block(r, nzu + i * gx, cx, gx) = X.A;
    cz_.lo0.segment(r, cx) = X.b;
    cz_.hi0.segment(r, cx) = X.b;
  }
  cz_.A.block(r, 0, nzeta, nzeta).setIdentity();
  cz_.lo0.segment(r, nzeta).setConstant(-1.0);
  cz_.hi0.segment(r, nzeta).setConstant(1.0);
  // The 480 dynamics rows are equalities (rho x1e3); the plain spectral rule suits them.
  SolverOptions cz_opt = opt;
  if (cz_opt.rho == 0.0) cz_opt.rho_scale = 1.0;
  admm_ = std::make_unique<DenseAdmm>(cz_.H, cz_.A, cz_.lo0, cz_.hi0, cz_opt,
                                      std::vector<ShiftSegment>{{0, gu, M}, {nzu, gx, N}},
                                      std::vector<ShiftSegment>{{0, n, N}, {N * n + M * cu + N * cx, gu, M},
                                                                {N * n + M * cu + N * cx + nzu, gx, N}});
  nd_ = nd;
  n_ = n;
  M_ = M;
  m_ = m;
  Tu_ = d.Tu;
  us_.setZero(m);
  f_.resize(nzeta);
  lo_.resize(rows);
  hi_.resize(rows);
  inner_.z.resize(nzeta);
  inner_.y.resize(rows);
  res_.z.resize(M * m);
  fp_.resize(polytope.nz());
  tz_.resize(polytope.nz());
  lop_.resize(polytope.nc());
  hip_.resize(polytope.nc());
  res_.y.setZero(polytope.nc());
}

const SolveResult& AdmmCz::solve(const Eigen::VectorXd& x0) {
  if (!valid_state(x0, cz_.nx(), res_)) return res_;
  cz_.instance_into(x0, f_, lo_, hi_);
  admm_->solve(f_, lo_, hi_, inner_);
  // (4.47): u_hat = c_u + G_u zeta_u (- U_s), for every step of the horizon.
  res_.z = cu_full_;
  if (nd_ > 0) {
    us_.noalias() = Tu_ * x0.segment(n_, nd_);
    for (int i = 0; i < M_; ++i) res_.z.segment(i * m_, m_) -= us_;
  }
  res_.z.noalias() += Gu_full_ * inner_.z.head(Gu_full_.cols());
  res_.status = inner_.status;
  res_.iterations = inner_.iterations;
  res_.primal_residual = inner_.primal_residual;
  res_.dual_residual = inner_.dual_residual;
  // Objective of the polytope formulation at u_hat (the same meaning for every solver).
  polytope_.instance_into(x0, fp_, lop_, hip_);
  tz_.noalias() = polytope_.H * res_.z;
  res_.objective = 0.5 * res_.z.dot(tz_) + fp_.dot(res_.z);
  res_.restarts = inner_.restarts;
  res_.solve_us = inner_.solve_us;
  return res_;
}

}  // namespace tmpc::detail
