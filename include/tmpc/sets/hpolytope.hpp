// H-polytopes {x : H x <= k} and the exact Pontryagin difference with a zonotope,
// thesis Proposition 3.1 (Raimondo et al. 2013):
//   P - Z = {x : h_i'x <= k_i - h_i'c - ||h_i'G||_1}
#pragma once

#include <Eigen/Core>

namespace tmpc {

struct Zonotope;
struct Box;

struct HPolytope {
  Eigen::MatrixXd H;
  Eigen::VectorXd k;

  HPolytope() = default;
  HPolytope(Eigen::MatrixXd h, Eigen::VectorXd rhs);
  static HPolytope from_box(const Box& b);

  int dim() const { return static_cast<int>(H.cols()); }
  bool contains(const Eigen::VectorXd& x, double tol = 0.0) const;
  /// Exact Pontryagin difference P - Z (same normals, tightened offsets).
  HPolytope minus(const Zonotope& z) const;
};

}  // namespace tmpc
