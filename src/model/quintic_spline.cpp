// C4 quintic splines (see quintic_spline.hpp).
#include "tmpc/model/quintic_spline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

namespace tmpc {

namespace {

/// d-th derivative of tau^j (coefficient of c_j) at tau.
double power_derivative(int j, int d, double tau) {
  if (d > j) return 0.0;
  double f = 1.0;
  for (int k = 0; k < d; ++k) f *= static_cast<double>(j - k);
  return f * std::pow(tau, j - d);
}

}  // namespace

QuinticSpline::QuinticSpline(std::vector<double> t, const std::vector<double>& y, Ends ends, double v0, double a0,
                             double v1, double a1)
    : t_(std::move(t)) {
  const std::size_t pts = t_.size();
  if (pts < 2 || y.size() != pts) {
    throw std::invalid_argument("quintic spline: need at least 2 knots with one value each (got " +
                                std::to_string(pts) + " knots, " + std::to_string(y.size()) + " values)");
  }
  for (std::size_t i = 0; i + 1 < pts; ++i) {
    if (!(t_[i + 1] > t_[i])) throw std::invalid_argument("quintic spline: knots must increase (knot " + std::to_string(i + 1) + ")");
  }
  for (double v : y) {
    if (!std::isfinite(v)) throw std::invalid_argument("quintic spline: non-finite value");
  }
  const int n = static_cast<int>(pts) - 1;  // segments
  const int N = 6 * n;
  std::vector<Eigen::Triplet<double>> T;
  T.reserve(static_cast<std::size_t>(N) * 7);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(N);
  int row = 0;
  auto add_derivative = [&](int seg, int d, double tau, double sign) {
    for (int j = d; j < 6; ++j) T.emplace_back(row, 6 * seg + j, sign * power_derivative(j, d, tau));
  };
  // End conditions at t_0.
  const int first_orders[2] = {ends == Ends::Clamped ? 1 : 3, ends == Ends::Clamped ? 2 : 4};
  const double first_values[2] = {ends == Ends::Clamped ? v0 : 0.0, ends == Ends::Clamped ? a0 : 0.0};
  for (int e = 0; e < 2; ++e) {
    add_derivative(0, first_orders[e], 0.0, 1.0);
    rhs(row++) = first_values[e];
  }
  for (int k = 0; k < n; ++k) {
    const double h = t_[static_cast<std::size_t>(k + 1)] - t_[static_cast<std::size_t>(k)];
    add_derivative(k, 0, 0.0, 1.0);
    rhs(row++) = y[static_cast<std::size_t>(k)];
    add_derivative(k, 0, h, 1.0);
    rhs(row++) = y[static_cast<std::size_t>(k + 1)];
    if (k + 1 < n) {
      for (int d = 1; d <= 4; ++d) {
        add_derivative(k, d, h, 1.0);
        add_derivative(k + 1, d, 0.0, -1.0);
        rhs(row++) = 0.0;
      }
    }
  }
  const double h_last = t_.back() - t_[pts - 2];
  const double last_values[2] = {ends == Ends::Clamped ? v1 : 0.0, ends == Ends::Clamped ? a1 : 0.0};
  for (int e = 0; e < 2; ++e) {
    add_derivative(n - 1, first_orders[e], h_last, 1.0);
    rhs(row++) = last_values[e];
  }
  if (row != N) throw std::logic_error("quintic spline: " + std::to_string(row) + " equations for " + std::to_string(N));
  Eigen::SparseMatrix<double> M(N, N);
  M.setFromTriplets(T.begin(), T.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(M);
  if (lu.info() != Eigen::Success) throw std::invalid_argument("quintic spline: singular system (knots too close?)");
  const Eigen::VectorXd c = lu.solve(rhs);
  if (!c.allFinite()) throw std::invalid_argument("quintic spline: the solution is not finite");
  c_.resize(n, 6);
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < 6; ++j) c_(k, j) = c(6 * k + j);
  }
}

void QuinticSpline::evaluate(double t, double& y, double& dy, double& ddy, double& dddy) const {
  const bool before = t <= t_.front(), after = t >= t_.back();
  const int n = static_cast<int>(c_.rows());
  int k = 0;
  if (after) {
    k = n - 1;
  } else if (!before) {
    k = static_cast<int>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin()) - 1;
    k = std::clamp(k, 0, n - 1);
  }
  const double tau = before ? 0.0 : (after ? t_.back() - t_[static_cast<std::size_t>(n - 1)] : t - t_[static_cast<std::size_t>(k)]);
  const auto c = c_.row(k);
  y = ((((c(5) * tau + c(4)) * tau + c(3)) * tau + c(2)) * tau + c(1)) * tau + c(0);
  dy = (((5 * c(5) * tau + 4 * c(4)) * tau + 3 * c(3)) * tau + 2 * c(2)) * tau + c(1);
  ddy = ((20 * c(5) * tau + 12 * c(4)) * tau + 6 * c(3)) * tau + 2 * c(2);
  dddy = (60 * c(5) * tau + 24 * c(4)) * tau + 6 * c(3);
  if (before || after) {
    // Outside the knots the path holds its end point.
    if ((before && t < t_.front()) || (after && t > t_.back())) dy = ddy = dddy = 0.0;
  }
}

double QuinticSpline::value(double t) const {
  double y, dy, ddy, dddy;
  evaluate(t, y, dy, ddy, dddy);
  return y;
}

}  // namespace tmpc
