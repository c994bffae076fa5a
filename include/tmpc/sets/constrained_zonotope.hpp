// Constrained zonotopes (thesis Definition 3.4, Scott et al. 2016):
//   Z = {c + G xi : ||xi||_inf <= 1, A xi = b}
// Exact conversion from a bounded H-polytope {x : H x <= k} (Scott Thm 1): with a
// box <c0, G0> containing P and lower bounds s_i <= h_i'x over P (here the exact
// valid bound s_i = h_i'c0 - ||G0'h_i||_1),
//   P = {[G0 0], c0, [H G0, diag((s - k)/2)], (k + s)/2 - H c0}.
// Boxes and zonotopes stay constraint-free.
#pragma once

#include <Eigen/Core>

namespace tmpc {

struct Box;
struct HPolytope;
struct Zonotope;

struct ConstrainedZonotope {
  Eigen::VectorXd c;
  Eigen::MatrixXd G;
  Eigen::MatrixXd A;  // nc x ng
  Eigen::VectorXd b;

  static ConstrainedZonotope from_zonotope(const Zonotope& z);
  static ConstrainedZonotope from_box(const Box& b);
  /// Exact, for a bounded polytope contained in `bounding_box`.
  static ConstrainedZonotope from_hpolytope(const HPolytope& p, const Box& bounding_box);

  int dim() const { return static_cast<int>(c.size()); }
  int generators() const { return static_cast<int>(G.cols()); }
  int constraints() const { return static_cast<int>(A.rows()); }
  /// The point for factors xi (no check of the constraints).
  Eigen::VectorXd point(const Eigen::VectorXd& xi) const { return c + G * xi; }
};

}  // namespace tmpc
