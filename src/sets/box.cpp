#include "tmpc/sets/box.hpp"

#include <cmath>
#include <stdexcept>

#include "tmpc/sets/zonotope.hpp"

namespace tmpc {

Box::Box(Eigen::VectorXd lower, Eigen::VectorXd upper) : lo(std::move(lower)), hi(std::move(upper)) {
  if (lo.size() != hi.size()) {
    throw std::invalid_argument("Box: lower size " + std::to_string(lo.size()) + " != upper size " +
                                std::to_string(hi.size()));
  }
}

Box Box::symmetric(const Eigen::VectorXd& half_width) { return Box(-half_width, half_width); }

int Box::first_empty_dimension() const {
  for (int i = 0; i < dim(); ++i) {
    if (!(lo(i) <= hi(i))) return i;
  }
  return -1;
}
bool Box::empty() const { return first_empty_dimension() >= 0; }

bool Box::contains(const Eigen::VectorXd& x, double tol) const {
  return ((x - lo).array() >= -tol).all() && ((hi - x).array() >= -tol).all();
}

double Box::support(const Eigen::VectorXd& d) const {
  return d.dot(center()) + d.cwiseAbs().dot(half_width());
}

double Box::one_norm_radius() const { return (hi - lo).sum(); }

double Box::volume() const { return (hi - lo).prod(); }

Box Box::minus(const Zonotope& z) const {
  if (z.dim() != dim()) throw std::invalid_argument("Box::minus: dimensions differ");
  const Eigen::VectorXd r = z.radius();
  return Box(lo - z.c + r, hi - z.c - r);
}

Box Box::scaled(const Eigen::VectorXd& s) const {
  return Box(lo.cwiseProduct(s), hi.cwiseProduct(s));
}

}  // namespace tmpc
