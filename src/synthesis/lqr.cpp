#include "tmpc/synthesis/lqr.hpp"

#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

namespace tmpc {

double spectral_radius(const Eigen::MatrixXd& A) {
  return Eigen::EigenSolver<Eigen::MatrixXd>(A, false).eigenvalues().cwiseAbs().maxCoeff();
}

LqrResult solve_dlqr(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                     const Eigen::MatrixXd& R) {
  const Eigen::Index n = A.rows();
  // Doubling: A_{k+1} = A_k (I + G_k H_k)^-1 A_k, G_{k+1} = G_k + A_k (I + G_k H_k)^-1 G_k A_k',
  //           H_{k+1} = H_k + A_k' H_k (I + G_k H_k)^-1 A_k;  H_k -> P.
  Eigen::MatrixXd Ak = A;
  Eigen::MatrixXd Gk = B * R.ldlt().solve(B.transpose());
  Eigen::MatrixXd Hk = Q;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  LqrResult out;
  for (out.iterations = 1; out.iterations <= 100; ++out.iterations) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(I + Gk * Hk);
    const Eigen::MatrixXd AkInvA = lu.solve(Ak);
    const Eigen::MatrixXd Hn = Hk + Ak.transpose() * Hk * AkInvA;
    const Eigen::MatrixXd Gn = Gk + Ak * lu.solve(Gk) * Ak.transpose();
    const Eigen::MatrixXd An = Ak * AkInvA;
    const double change = (Hn - Hk).norm() / std::max(1.0, Hn.norm());
    Ak = An;
    Gk = 0.5 * (Gn + Gn.transpose());
    Hk = 0.5 * (Hn + Hn.transpose());
    if (!Hk.allFinite()) break;
    if (change < 1e-14) break;
  }
  out.P = Hk;
  if (!out.P.allFinite()) throw std::runtime_error("DARE: doubling diverged (is (A, B) stabilizable?)");
  const Eigen::MatrixXd S = R + B.transpose() * out.P * B;
  out.K = -S.ldlt().solve(B.transpose() * out.P * A);
  const Eigen::MatrixXd res =
      A.transpose() * out.P * A - out.P + Q - A.transpose() * out.P * B * S.ldlt().solve(B.transpose() * out.P * A);
  out.residual = res.norm() / out.P.norm();
  out.spectral_radius = spectral_radius(A + B * out.K);
  if (out.residual > 1e-8 || out.spectral_radius >= 1.0) {
    throw std::runtime_error("DARE: no stabilizing solution (residual " + std::to_string(out.residual) +
                             ", closed-loop spectral radius " + std::to_string(out.spectral_radius) + ")");
  }
  return out;
}

}  // namespace tmpc
