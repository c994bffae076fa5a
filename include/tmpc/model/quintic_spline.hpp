// Quintic splines with continuous derivatives up to the fourth (C4): the spline that
// minimizes the integral of the squared jerk through given points at given times
// (a minimum-jerk path is piecewise quintic with C4 joints). Per segment k,
// p_k(tau) = sum_j c_kj tau^j, tau = t - t_k in [0, h_k]; the 6 n coefficients solve
//   p_k(0) = y_k, p_k(h_k) = y_(k+1), p_k^(d)(h_k) = p_(k+1)^(d)(0) for d = 1..4,
// plus two end conditions at each end: clamped (velocity and acceleration given) or
// natural (third and fourth derivatives zero). The system is banded: a sparse LU.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace tmpc {

class QuinticSpline {
 public:
  enum class Ends { Clamped, Natural };
  QuinticSpline() = default;
  /// Knots strictly increasing (at least 2); Clamped takes v0, a0, v1, a1 at the ends.
  /// Throws std::invalid_argument for bad knots.
  QuinticSpline(std::vector<double> t, const std::vector<double>& y, Ends ends, double v0 = 0.0, double a0 = 0.0,
                double v1 = 0.0, double a1 = 0.0);
  /// Value and derivatives 1..3 at t (clamped to [t_0, t_n]: beyond the ends the value
  /// of the end point and, for a clamped spline ending at rest, zero derivatives).
  void evaluate(double t, double& y, double& dy, double& ddy, double& dddy) const;
  double value(double t) const;
  double start() const { return t_.front(); }
  double end() const { return t_.back(); }
  const std::vector<double>& knots() const { return t_; }

 private:
  std::vector<double> t_;
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> c_;
};

}  // namespace tmpc
