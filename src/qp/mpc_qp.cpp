#include "tmpc/qp/mpc_qp.hpp"

#include <Eigen/Eigenvalues>

#include <stdexcept>
#include <string>

namespace tmpc {

Eigen::MatrixXd MpcQpData::Wx() const {
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(N * n, N * n);
  for (int i = 0; i < N - 1; ++i) w.block(i * n, i * n, n, n) = Sigma_rho;
  w.block((N - 1) * n, (N - 1) * n, n, n) = L;
  return w;
}

Eigen::MatrixXd MpcQpData::Wu() const {
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(M * m, M * m);
  for (int i = 0; i < M - 1; ++i) w.block(i * m, i * m, m, m) = Sigma_lambda;
  w.block((M - 1) * m, (M - 1) * m, m, m) = static_cast<double>(N - M + 1) * Sigma_lambda;
  return w;
}

MpcQpData build_mpc_qp(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Sigma_rho,
                       const Eigen::MatrixXd& Sigma_lambda, const Eigen::MatrixXd& L, const Box& x_bar,
                       const Box& u_bar, int N, int M) {
  const int n = static_cast<int>(A.rows()), m = static_cast<int>(B.cols());
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("build_mpc_qp: " + what);
  };
  need(A.cols() == n && B.rows() == n, "A must be n x n and B n x m");
  need(Sigma_rho.rows() == n && Sigma_rho.cols() == n && L.rows() == n && L.cols() == n, "state weights must be n x n");
  need(Sigma_lambda.rows() == m && Sigma_lambda.cols() == m, "input weight must be m x m");
  need(x_bar.dim() == n && u_bar.dim() == m, "tightened sets have the wrong dimension");
  need(N >= 1 && M >= 1 && M <= N, "need 1 <= M <= N (got N = " + std::to_string(N) + ", M = " + std::to_string(M) + ")");
  MpcQpData d;
  d.n = n;
  d.m = m;
  d.N = N;
  d.M = M;
  d.A = A;
  d.B = B;
  d.Sigma_rho = Sigma_rho;
  d.Sigma_lambda = Sigma_lambda;
  d.L = L;
  d.x_bar = x_bar;
  d.u_bar = u_bar;
  // x(i+1) = A x(i) + B u(min(i, M-1)): block (i, j) of P is sum over the steps k <= i
  // whose input is u(j) of A^(i-k) B.
  std::vector<Eigen::MatrixXd> Apow(static_cast<std::size_t>(N) + 1);
  Apow[0] = Eigen::MatrixXd::Identity(n, n);
  for (int i = 1; i <= N; ++i) Apow[static_cast<std::size_t>(i)] = A * Apow[static_cast<std::size_t>(i - 1)];
  d.P = Eigen::MatrixXd::Zero(N * n, M * m);
  d.Q = Eigen::MatrixXd(N * n, n);
  for (int i = 0; i < N; ++i) {
    d.Q.block(i * n, 0, n, n) = Apow[static_cast<std::size_t>(i + 1)];
    for (int k = 0; k <= i; ++k) {
      const int j = std::min(k, M - 1);
      d.P.block(i * n, j * m, n, m) += Apow[static_cast<std::size_t>(i - k)] * B;
    }
  }
  const Eigen::MatrixXd Wx = d.Wx();
  d.H = 2.0 * (d.P.transpose() * Wx * d.P + d.Wu());
  d.H = 0.5 * (d.H + d.H.transpose());
  d.F = 2.0 * d.P.transpose() * Wx * d.Q;
  return d;
}

void make_offset_free(MpcQpData& d, const Eigen::MatrixXd& Tx, const Eigen::MatrixXd& Tu) {
  if (Tx.rows() != d.n || Tu.rows() != d.m || Tx.cols() != Tu.cols() || Tx.cols() == 0) {
    throw std::invalid_argument("make_offset_free: Tx (" + std::to_string(Tx.rows()) + "x" + std::to_string(Tx.cols()) +
                                ") and Tu (" + std::to_string(Tu.rows()) + "x" + std::to_string(Tu.cols()) +
                                ") disagree with n = " + std::to_string(d.n) + ", m = " + std::to_string(d.m));
  }
  if (d.rate_weighted()) throw std::invalid_argument("make_offset_free: call it before add_input_rate_weight (v_prev comes last)");
  d.redundant_rows.clear();  // certified for the other form
  d.domain = ParameterDomain{};
  d.Tx = Tx;
  d.Tu = Tu;
  // x(i) picks up (I + A + ... + A^(i-1)) c.
  d.Phi = Eigen::MatrixXd(d.N * d.n, d.n);
  Eigen::MatrixXd S = Eigen::MatrixXd::Identity(d.n, d.n);
  for (int i = 0; i < d.N; ++i) {
    d.Phi.middleRows(i * d.n, d.n) = S;
    S = Eigen::MatrixXd::Identity(d.n, d.n) + d.A * S;
  }
}

void add_input_rate_weight(MpcQpData& d, const Eigen::MatrixXd& Sigma_delta) {
  const int m = d.m;
  if (Sigma_delta.rows() != m || Sigma_delta.cols() != m) {
    throw std::invalid_argument("add_input_rate_weight: Sigma_delta is " + std::to_string(Sigma_delta.rows()) + "x" +
                                std::to_string(Sigma_delta.cols()) + ", expected " + std::to_string(m) + "x" +
                                std::to_string(m));
  }
  if (d.rate_weighted()) throw std::invalid_argument("add_input_rate_weight: the QP already has an input-rate weight");
  if (!Sigma_delta.allFinite() || (Sigma_delta - Sigma_delta.transpose()).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + Sigma_delta.cwiseAbs().maxCoeff())) {
    throw std::invalid_argument("add_input_rate_weight: Sigma_delta must be finite and symmetric");
  }
  if (Sigma_delta.isZero(0.0)) return;
  const double low = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Sigma_delta).eigenvalues().minCoeff();
  if (low < -1e-9 * Sigma_delta.cwiseAbs().maxCoeff()) {
    throw std::invalid_argument("add_input_rate_weight: Sigma_delta is not positive semidefinite (eigenvalue " +
                                std::to_string(low) + ")");
  }
  d.redundant_rows.clear();  // certified for the parameter without v_prev
  d.domain = ParameterDomain{};
  // Delta' (I (x) S) Delta: S on the diagonal blocks (twice for all but the last: each
  // u(i), i < M - 1, starts one difference and ends another), -S beside them.
  for (int i = 0; i < d.M; ++i) {
    d.H.block(i * m, i * m, m, m) += 2.0 * (i + 1 < d.M ? 2.0 : 1.0) * Sigma_delta;
    if (i > 0) {
      d.H.block(i * m, (i - 1) * m, m, m) -= 2.0 * Sigma_delta;
      d.H.block((i - 1) * m, i * m, m, m) -= 2.0 * Sigma_delta;
    }
  }
  d.Sigma_delta = Sigma_delta;
}

CondensedQp condensed_qp(const MpcQpData& d, const Eigen::VectorXd& x0) {
  if (x0.size() != d.n) {
    throw std::invalid_argument("condensed_qp: x0 has " + std::to_string(x0.size()) + " entries, expected " +
                                std::to_string(d.n));
  }
  CondensedQp qp;
  const int nz = d.variables();
  qp.H = d.H;
  qp.f = d.F * x0;
  qp.A = Eigen::MatrixXd(nz + d.N * d.n, nz);
  qp.A.topRows(nz).setIdentity();
  qp.A.bottomRows(d.N * d.n) = d.P;
  qp.lo.resize(qp.A.rows());
  qp.hi.resize(qp.A.rows());
  const Eigen::VectorXd Qx = d.Q * x0;
  for (int i = 0; i < d.M; ++i) {
    qp.lo.segment(i * d.m, d.m) = d.u_bar.lo;
    qp.hi.segment(i * d.m, d.m) = d.u_bar.hi;
  }
  for (int i = 0; i < d.N; ++i) {
    qp.lo.segment(nz + i * d.n, d.n) = d.x_bar.lo - Qx.segment(i * d.n, d.n);
    qp.hi.segment(nz + i * d.n, d.n) = d.x_bar.hi - Qx.segment(i * d.n, d.n);
  }
  const Eigen::MatrixXd Wx = d.Wx();
  qp.constant = Qx.dot(Wx * Qx);
  return qp;
}

double mpc_cost(const MpcQpData& d, const Eigen::VectorXd& x0, const Eigen::VectorXd& u_hat,
                const Eigen::VectorXd& v_prev) {
  const Eigen::VectorXd x_hat = d.P * u_hat + d.Q * x0;
  double v = x_hat.dot(d.Wx() * x_hat) + u_hat.dot(d.Wu() * u_hat);
  if (d.rate_weighted()) {
    Eigen::VectorXd before = v_prev.size() == d.m ? v_prev : Eigen::VectorXd::Zero(d.m);
    for (int i = 0; i < d.M; ++i) {
      const Eigen::VectorXd step = u_hat.segment(i * d.m, d.m) - before;
      v += step.dot(d.Sigma_delta * step);
      before = u_hat.segment(i * d.m, d.m);
    }
  }
  return v;
}

}  // namespace tmpc
