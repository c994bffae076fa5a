// Zonotopes (thesis Definition 3.3): Z = c + G B^r, B = [-1, 1]. Exact operations:
//   support function   h_Z(d) = d'c + ||G'd||_1
//   linear map         R Z = <R c, R G>
//   Minkowski sum      Z1 + Z2 = <c1 + c2, [G1 G2]>
//   interval hull      c +- sum_j |G_ij|  (outer box, exact for the box's faces)
#pragma once

#include <Eigen/Core>

namespace tmpc {

struct Box;

struct Zonotope {
  Eigen::VectorXd c;
  Eigen::MatrixXd G;

  Zonotope() = default;
  Zonotope(Eigen::VectorXd center, Eigen::MatrixXd generators);
  static Zonotope from_box(const Box& b);

  int dim() const { return static_cast<int>(c.size()); }
  int order() const { return static_cast<int>(G.cols()); }

  /// Support function, exact: h(d) = d'c + ||G'd||_1.
  double support(const Eigen::VectorXd& d) const;
  /// Exact image under a linear map.
  Zonotope map(const Eigen::MatrixXd& R) const;
  /// Exact Minkowski sum.
  Zonotope plus(const Zonotope& other) const;
  /// Outer box (interval hull), exact on the coordinate directions.
  Box interval_hull() const;
  /// Row sums of |G|: half-widths of the interval hull.
  Eigen::VectorXd radius() const;
};

}  // namespace tmpc
