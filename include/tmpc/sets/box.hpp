// Axis-aligned boxes {x : lo <= x <= hi} and their exact Pontryagin difference with
// a zonotope (thesis Proposition 3.1 on the 2n faces of the box):
//   B - Z = {x : lo + (c + r) <= ... }: hi' = hi - c - r, lo' = lo - c + r, r = |G| 1
#pragma once

#include <string>

#include <Eigen/Core>

namespace tmpc {

struct Zonotope;

struct Box {
  Eigen::VectorXd lo, hi;

  Box() = default;
  Box(Eigen::VectorXd lower, Eigen::VectorXd upper);
  static Box symmetric(const Eigen::VectorXd& half_width);

  int dim() const { return static_cast<int>(lo.size()); }
  bool empty() const;
  /// First dimension with lo > hi, or -1.
  int first_empty_dimension() const;
  bool contains(const Eigen::VectorXd& x, double tol = 0.0) const;
  Eigen::VectorXd center() const { return 0.5 * (lo + hi); }
  Eigen::VectorXd half_width() const { return 0.5 * (hi - lo); }
  double support(const Eigen::VectorXd& d) const;
  /// 1-norm radius (sum of the interval diameters) and volume (product), thesis Table 5.1.
  double one_norm_radius() const;
  double volume() const;

  /// Exact Pontryagin difference B - Z (a box; possibly empty).
  Box minus(const Zonotope& z) const;
  Box scaled(const Eigen::VectorXd& s) const;  // diag(s) B, s > 0
};

}  // namespace tmpc
