// Tracking error (see tracking_error.hpp).
#include "tmpc/runtime/tracking_error.hpp"

#include <cmath>

#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {

const Eigen::VectorXd& TrackingError::update(const State20& x, const ReferencePoint& r) {
  xt_.head<10>() = x.head<10>() - r.q;
  xt_(kPsi) = std::remainder(xt_(kPsi), 2.0 * M_PI);
  xt_.segment<10>(10) = x.tail<10>() - r.qd;
  xt_.tail<4>() = integral_;
  return xt_;
}

void TrackingError::integrate(double dt) {
  integral_ += dt * Eigen::Vector4d(xt_(kX), xt_(kY), xt_(kZ), xt_(kPsi));
}

}  // namespace tmpc
