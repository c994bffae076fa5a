// Tracking error (see tracking_error.hpp).
#include "tmpc/runtime/tracking_error.hpp"

#include <cmath>

#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {

void TrackingError::measured(const State20& x, const ReferencePoint& r, Eigen::VectorXd& e) {
  e.head<10>() = x.head<10>() - r.q;
  e(kPsi) = std::remainder(e(kPsi), 2.0 * M_PI);
  e.segment<10>(10) = x.tail<10>() - r.qd;
}

const Eigen::VectorXd& TrackingError::update(const State20& x, const ReferencePoint& r) {
  measured(x, r, xt_);
  xt_.tail<4>() = integral_;
  return xt_;
}

void TrackingError::integrate(double dt) {
  integral_ += dt * Eigen::Vector4d(xt_(kX), xt_(kY), xt_(kZ), xt_(kPsi));
}

std::string error_state_name(int i) {
  static const char* const integrals[] = {"x", "y", "z", "psi"};
  if (i >= 0 && i < kNq) return kCoordNames[static_cast<std::size_t>(i)];
  if (i >= kNq && i < 2 * kNq) return std::string("d_") + kCoordNames[static_cast<std::size_t>(i - kNq)];
  if (i >= 2 * kNq && i < 2 * kNq + 4) return std::string("int_") + integrals[i - 2 * kNq];
  return "state_" + std::to_string(i);
}

}  // namespace tmpc
