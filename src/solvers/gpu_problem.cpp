// Flat float QP data for the GPU solver (see gpu_problem.hpp).
#include "tmpc/solvers/gpu_problem.hpp"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace tmpc {

namespace {
template <class R>
std::vector<R> flat(const Eigen::MatrixXd& M) {  // row-major (a vector is one column)
  std::vector<R> v(static_cast<std::size_t>(M.size()));
  for (Eigen::Index i = 0; i < M.rows(); ++i)
    for (Eigen::Index j = 0; j < M.cols(); ++j) v[static_cast<std::size_t>(i * M.cols() + j)] = static_cast<R>(M(i, j));
  return v;
}

template <class R>
gpu::BasicAdmmProblem<R> build(const MpcQpData& d, const SolverOptions& options) {
  options.validate();
  if (options.equilibrate) throw std::invalid_argument("GPU solver: option equilibrate is not implemented on the device");
  const ParametricQp qp = ParametricQp::from_mpc(d);
  gpu::BasicAdmmProblem<R> p;
  p.nz = qp.nz();
  p.nc = qp.nc();
  p.nx = qp.nx();
  p.m = d.m;
  p.M = d.M;
  p.n = d.n;
  p.N = d.N;
  // exact variant: the CPU DenseAdmm's set-up (dense_admm.cpp) without equilibration.
  const double rho = options.rho > 0.0 ? options.rho : options.rho_scale * spectral_rho(qp.H, qp.A);
  Eigen::VectorXd rv(qp.nc());
  for (int i = 0; i < qp.nc(); ++i) rv(i) = qp.lo0(i) == qp.hi0(i) ? 1e3 * rho : rho;
  Eigen::MatrixXd K = qp.H + qp.A.transpose() * rv.asDiagonal() * qp.A;
  K.diagonal().array() += options.sigma;
  const Eigen::LLT<Eigen::MatrixXd> llt(K);
  if (llt.info() != Eigen::Success) throw std::invalid_argument("GPU solver: H + sigma I + A'RA is not positive definite");
  p.rho = static_cast<R>(rho);
  p.H = flat<R>(qp.H);
  p.f0 = flat<R>(qp.f0);
  p.F = flat<R>(qp.F);
  p.A = flat<R>(qp.A);
  p.E = flat<R>(qp.E);
  p.lo0 = flat<R>(qp.lo0);
  p.hi0 = flat<R>(qp.hi0);
  p.rho_vec = flat<R>(rv);
  p.Kinv = flat<R>(Eigen::MatrixXd(llt.solve(Eigen::MatrixXd::Identity(qp.nz(), qp.nz()))));
  // thesis variant: AdmmThesis's set-up (admm_thesis.cpp).
  const double rt = options.rho > 0.0 ? options.rho : spectral_rho(qp.H, qp.A);
  p.rho_thesis = static_cast<R>(rt);
  p.P = flat<R>(d.P);
  // Q acts on the state part of x0 (the offset-free d part moves only the exact
  // variant's bounds, through E; the thesis variant refuses that form).
  Eigen::MatrixXd Qx = Eigen::MatrixXd::Zero(d.Q.rows(), qp.nx());
  Qx.leftCols(d.n) = d.Q;
  p.Q = flat<R>(Qx);
  p.H1inv = flat<R>(Eigen::MatrixXd((rt * d.P.transpose() * d.P + 2.0 * d.Wu()).inverse()));
  p.H2diag = flat<R>(Eigen::VectorXd((rt + 2.0 * d.Sigma_rho.diagonal().array()).inverse().matrix()));
  p.H2last = flat<R>(Eigen::MatrixXd((rt * Eigen::MatrixXd::Identity(d.n, d.n) + 2.0 * d.L).inverse()));
  p.xlo = flat<R>(Eigen::VectorXd(d.x_bar.lo.replicate(d.N, 1)));
  p.xhi = flat<R>(Eigen::VectorXd(d.x_bar.hi.replicate(d.N, 1)));
  p.ulo = flat<R>(Eigen::VectorXd(d.u_bar.lo.replicate(d.M, 1)));
  p.uhi = flat<R>(Eigen::VectorXd(d.u_bar.hi.replicate(d.M, 1)));
  // Block form of P: G_l = A^l B, S_l = G_0 + ... + G_l, used only if it rebuilds P.
  {
    std::vector<Eigen::MatrixXd> G(static_cast<std::size_t>(d.N)), S(static_cast<std::size_t>(d.N));
    Eigen::MatrixXd Al = Eigen::MatrixXd::Identity(d.n, d.n);
    for (int l = 0; l < d.N; ++l) {
      G[static_cast<std::size_t>(l)] = Al * d.B;
      S[static_cast<std::size_t>(l)] = l == 0 ? G[0] : Eigen::MatrixXd(S[static_cast<std::size_t>(l - 1)] + G[static_cast<std::size_t>(l)]);
      Al = d.A * Al;
    }
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(d.N * d.n, d.M * d.m);
    for (int k = 0; k < d.N; ++k) {
      for (int j = 0; j < d.M; ++j) {
        if (j < d.M - 1 && j <= k) P.block(k * d.n, j * d.m, d.n, d.m) = G[static_cast<std::size_t>(k - j)];
        if (j == d.M - 1 && k >= d.M - 1) P.block(k * d.n, j * d.m, d.n, d.m) = S[static_cast<std::size_t>(k - d.M + 1)];
      }
    }
    if ((P - d.P).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, d.P.cwiseAbs().maxCoeff())) {
      for (int l = 0; l < d.N; ++l) {
        const std::vector<R> g = flat<R>(G[static_cast<std::size_t>(l)]), s = flat<R>(S[static_cast<std::size_t>(l)]);
        p.Gblk.insert(p.Gblk.end(), g.begin(), g.end());
        p.Sblk.insert(p.Sblk.end(), s.begin(), s.end());
      }
    }
  }
  const char* bad = p.check();
  if (bad[0] != '\0') throw std::logic_error(std::string("make_gpu_problem: ") + bad);
  return p;
}
}  // namespace

gpu::AdmmProblem make_gpu_problem(const MpcQpData& d, const SolverOptions& options) { return build<float>(d, options); }

gpu::BasicAdmmProblem<double> make_gpu_problem_fp64(const MpcQpData& d, const SolverOptions& options) {
  return build<double>(d, options);
}

gpu::AdmmSettings make_gpu_settings(const SolverOptions& o, int variant) {
  o.validate();
  gpu::AdmmSettings s;
  s.variant = variant;
  s.eps_abs = static_cast<float>(o.eps_abs);
  s.eps_rel = variant == gpu::kExact ? static_cast<float>(o.eps_rel) : 0.0f;
  s.max_iterations = o.max_iterations;
  s.check_every = o.check_every;
  s.r = static_cast<float>(o.r);
  s.s = static_cast<float>(o.s);
  s.nesterov = variant == gpu::kThesis || o.nesterov ? 1 : 0;
  s.eta = static_cast<float>(o.eta);
  s.sigma = static_cast<float>(o.sigma);
  s.eps_pinf = static_cast<float>(o.eps_pinf);
  s.warm_start = o.warm_start ? 1 : 0;
  s.time_budget_ns = static_cast<long long>(o.time_budget_us * 1e3);
  return s;
}

SolverOptions cpu_twin_options(SolverOptions o) {
  o.adaptive_rho = false;
  o.polish = false;
  o.equilibrate = false;
  return o;
}

}  // namespace tmpc
