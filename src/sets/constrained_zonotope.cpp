#include "tmpc/sets/constrained_zonotope.hpp"

#include <stdexcept>

#include "tmpc/sets/box.hpp"
#include "tmpc/sets/hpolytope.hpp"
#include "tmpc/sets/zonotope.hpp"

namespace tmpc {

ConstrainedZonotope ConstrainedZonotope::from_zonotope(const Zonotope& z) {
  ConstrainedZonotope cz;
  cz.c = z.c;
  cz.G = z.G;
  cz.A = Eigen::MatrixXd::Zero(0, z.order());
  cz.b = Eigen::VectorXd::Zero(0);
  return cz;
}

ConstrainedZonotope ConstrainedZonotope::from_box(const Box& b) { return from_zonotope(Zonotope::from_box(b)); }

ConstrainedZonotope ConstrainedZonotope::from_hpolytope(const HPolytope& p, const Box& bounding_box) {
  if (bounding_box.dim() != p.dim()) throw std::invalid_argument("from_hpolytope: bounding box dimension differs");
  const Zonotope z0 = Zonotope::from_box(bounding_box);
  const int n = p.dim();
  const int nh = static_cast<int>(p.H.rows());
  // Valid lower bounds of h_i'x over the bounding box, hence over P.
  const Eigen::VectorXd s = p.H * z0.c - (p.H * z0.G).cwiseAbs().rowwise().sum();
  ConstrainedZonotope cz;
  cz.c = z0.c;
  cz.G = Eigen::MatrixXd::Zero(n, n + nh);
  cz.G.leftCols(n) = z0.G;
  cz.A = Eigen::MatrixXd::Zero(nh, n + nh);
  cz.A.leftCols(n) = p.H * z0.G;
  cz.A.rightCols(nh) = ((s - p.k) / 2.0).asDiagonal();
  cz.b = (p.k + s) / 2.0 - p.H * z0.c;
  return cz;
}

}  // namespace tmpc
