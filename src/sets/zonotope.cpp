#include "tmpc/sets/zonotope.hpp"

#include <stdexcept>

#include "tmpc/sets/box.hpp"

namespace tmpc {

Zonotope::Zonotope(Eigen::VectorXd center, Eigen::MatrixXd generators) : c(std::move(center)), G(std::move(generators)) {
  if (G.rows() != c.size()) {
    throw std::invalid_argument("Zonotope: generator rows " + std::to_string(G.rows()) + " != center size " +
                                std::to_string(c.size()));
  }
}

Zonotope Zonotope::from_box(const Box& b) {
  return Zonotope(b.center(), Eigen::MatrixXd(b.half_width().asDiagonal()));
}

double Zonotope::support(const Eigen::VectorXd& d) const {
  return d.dot(c) + (G.transpose() * d).cwiseAbs().sum();
}

Zonotope Zonotope::map(const Eigen::MatrixXd& R) const { return Zonotope(R * c, R * G); }

Zonotope Zonotope::plus(const Zonotope& o) const {
  if (o.dim() != dim()) throw std::invalid_argument("Zonotope::plus: dimensions differ");
  Eigen::MatrixXd g(dim(), order() + o.order());
  g << G, o.G;
  return Zonotope(c + o.c, std::move(g));
}

Eigen::VectorXd Zonotope::radius() const { return G.cwiseAbs().rowwise().sum(); }

Box Zonotope::interval_hull() const {
  const Eigen::VectorXd r = radius();
  return Box(c - r, c + r);
}

}  // namespace tmpc
