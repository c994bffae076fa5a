#include "tmpc/qp/disturbance_target.hpp"

#include <stdexcept>
#include <string>

#include <Eigen/Dense>

namespace tmpc {

DisturbanceTarget steady_state_target(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                                      const std::vector<int>& zero_states) {
  const Eigen::Index n = A.rows(), m = B.cols(), nd = D.cols();
  if (A.cols() != n || B.rows() != n || D.rows() != n) {
    throw std::invalid_argument("steady_state_target: A " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()) +
                                ", B " + std::to_string(B.rows()) + "x" + std::to_string(B.cols()) + ", D " +
                                std::to_string(D.rows()) + "x" + std::to_string(D.cols()) + " disagree");
  }
  const Eigen::Index k = static_cast<Eigen::Index>(zero_states.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n + k, n + m);
  S.topLeftCorner(n, n) = Eigen::MatrixXd::Identity(n, n) - A;
  S.topRightCorner(n, m) = -B;
  for (Eigen::Index r = 0; r < k; ++r) {
    const int i = zero_states[static_cast<std::size_t>(r)];
    if (i < 0 || i >= n) throw std::invalid_argument("steady_state_target: zero state " + std::to_string(i) + " out of range");
    S(n + r, i) = 1.0;
  }
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + k, nd);
  rhs.topRows(n) = D;
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(S);
  const Eigen::MatrixXd sol = cod.solve(rhs);
  for (Eigen::Index j = 0; j < nd; ++j) {
    const double res = (S * sol.col(j) - rhs.col(j)).norm();
    if (!(res <= 1e-8 * std::max(1.0, rhs.col(j).norm()))) {
      throw std::invalid_argument("steady_state_target: disturbance channel " + std::to_string(j) +
                                  " has no steady state with the listed states at zero (residual " +
                                  std::to_string(res) + ")");
    }
  }
  DisturbanceTarget t;
  t.Tx = sol.topRows(n);
  t.Tu = sol.bottomRows(m);
  return t;
}

Eigen::MatrixXd disturbance_pseudo_inverse(const Eigen::MatrixXd& D, const std::vector<int>& rows) {
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), D.rows());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r] < 0 || rows[r] >= D.rows()) {
      throw std::invalid_argument("disturbance_pseudo_inverse: row " + std::to_string(rows[r]) + " out of range");
    }
    S(static_cast<Eigen::Index>(r), rows[r]) = 1.0;
  }
  const Eigen::MatrixXd SD = S * D;
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(SD);
  if (qr.rank() < D.cols()) {
    throw std::invalid_argument("disturbance_pseudo_inverse: D on the " + std::to_string(rows.size()) +
                                " observed rows has rank " + std::to_string(qr.rank()) + " < " +
                                std::to_string(D.cols()));
  }
  // Full column rank: the QR's solve is the least-squares solution, (SD)^+ = qr^-1.
  return qr.solve(Eigen::MatrixXd::Identity(SD.rows(), SD.rows())) * S;
}

}  // namespace tmpc
