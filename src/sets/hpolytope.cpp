#include "tmpc/sets/hpolytope.hpp"

#include <stdexcept>

#include "tmpc/sets/box.hpp"
#include "tmpc/sets/zonotope.hpp"

namespace tmpc {

HPolytope::HPolytope(Eigen::MatrixXd h, Eigen::VectorXd rhs) : H(std::move(h)), k(std::move(rhs)) {
  if (H.rows() != k.size()) {
    throw std::invalid_argument("HPolytope: " + std::to_string(H.rows()) + " normals but " + std::to_string(k.size()) +
                                " offsets");
  }
}

HPolytope HPolytope::from_box(const Box& b) {
  const int n = b.dim();
  Eigen::MatrixXd h(2 * n, n);
  h << Eigen::MatrixXd::Identity(n, n), -Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd rhs(2 * n);
  rhs << b.hi, -b.lo;
  return HPolytope(std::move(h), std::move(rhs));
}

bool HPolytope::contains(const Eigen::VectorXd& x, double tol) const {
  return ((H * x - k).array() <= tol).all();
}

HPolytope HPolytope::minus(const Zonotope& z) const {
  if (z.dim() != dim()) throw std::invalid_argument("HPolytope::minus: dimensions differ");
  // Proposition 3.1: k_i' = k_i - h_i'c - ||h_i'G||_1.
  const Eigen::VectorXd shrink = H * z.c + (H * z.G).cwiseAbs().rowwise().sum();
  return HPolytope(H, k - shrink);
}

}  // namespace tmpc
