#include "tmpc/solvers/kkt.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace tmpc {

double KktResiduals::max() const { return std::max({stationarity, primal, complementarity, dual_sign}); }

KktResiduals kkt_residuals(const CondensedQp& qp, const Eigen::VectorXd& z, const Eigen::VectorXd& y) {
  KktResiduals r;
  const Eigen::VectorXd Az = qp.A * z;
  r.stationarity = (qp.H * z + qp.f + qp.A.transpose() * y).cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < Az.size(); ++i) {
    r.primal = std::max({r.primal, qp.lo(i) - Az(i), Az(i) - qp.hi(i)});
    const double yp = std::max(y(i), 0.0), ym = std::max(-y(i), 0.0);
    if (std::isfinite(qp.hi(i))) {
      r.complementarity = std::max(r.complementarity, std::abs(yp * (qp.hi(i) - Az(i))));
    } else {
      r.dual_sign = std::max(r.dual_sign, yp);
    }
    if (std::isfinite(qp.lo(i))) {
      r.complementarity = std::max(r.complementarity, std::abs(ym * (Az(i) - qp.lo(i))));
    } else {
      r.dual_sign = std::max(r.dual_sign, ym);
    }
  }
  return r;
}

Eigen::VectorXd estimate_multipliers(const CondensedQp& qp, const Eigen::VectorXd& z, double tol) {
  const Eigen::VectorXd Az = qp.A * z;
  std::vector<Eigen::Index> rows;
  std::vector<double> sign;
  for (Eigen::Index i = 0; i < Az.size(); ++i) {
    if (qp.hi(i) - Az(i) <= tol) {
      rows.push_back(i);
      sign.push_back(1.0);
    } else if (Az(i) - qp.lo(i) <= tol) {
      rows.push_back(i);
      sign.push_back(-1.0);
    }
  }
  Eigen::VectorXd y = Eigen::VectorXd::Zero(Az.size());
  if (rows.empty()) return y;
  Eigen::MatrixXd At(qp.A.cols(), static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) At.col(static_cast<Eigen::Index>(k)) = qp.A.row(rows[k]).transpose();
  const Eigen::VectorXd g = -(qp.H * z + qp.f);
  const Eigen::VectorXd ya = At.completeOrthogonalDecomposition().solve(g);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double v = ya(static_cast<Eigen::Index>(k));
    // Keep the sign the bound allows (an equality row takes any sign).
    y(rows[k]) = (qp.lo(rows[k]) == qp.hi(rows[k])) ? v : (sign[k] > 0 ? std::max(v, 0.0) : std::min(v, 0.0));
  }
  return y;
}

double qp_objective(const CondensedQp& qp, const Eigen::VectorXd& z) {
  return 0.5 * z.dot(qp.H * z) + qp.f.dot(z) + qp.constant;
}

}  // namespace tmpc
