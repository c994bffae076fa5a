// Tracking error (see tracking_error.hpp).
#include "tmpc/runtime/tracking_error.hpp"

#include <cmath>

namespace tmpc {

TrackingError::TrackingError(std::vector<StateKind> kinds, std::vector<int> integrated)
    : kinds_(std::move(kinds)),
      integrated_(std::move(integrated)),
      xt_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(kinds_.size() + integrated_.size()))),
      integral_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(integrated_.size()))) {}

void TrackingError::measured(const Eigen::VectorXd& x, const Eigen::VectorXd& x_r, Eigen::VectorXd& e) const {
  const Eigen::Index p = static_cast<Eigen::Index>(kinds_.size());
  e.head(p) = x.head(p) - x_r.head(p);
  for (Eigen::Index i = 0; i < p; ++i) {
    if (kinds_[static_cast<std::size_t>(i)] == StateKind::Yaw) e(i) = std::remainder(e(i), 2.0 * M_PI);
  }
}

const Eigen::VectorXd& TrackingError::update(const Eigen::VectorXd& x, const Eigen::VectorXd& x_r) {
  measured(x, x_r, xt_);
  if (join_pending_) {
    join_.start(xt_);
    join_pending_ = false;
    t_ = 0.0;
  }
  join_.apply(t_, xt_);
  xt_.tail(integral_.size()) = integral_;
  return xt_;
}

void TrackingError::integrate(double dt) {
  for (std::size_t i = 0; i < integrated_.size(); ++i) {
    integral_(static_cast<Eigen::Index>(i)) += dt * xt_(integrated_[i]);
  }
  t_ += dt;
}

void TrackingError::set_join(ReferenceJoinSettings s) {
  join_pending_ = s.enabled();
  join_ = ReferenceJoin(std::move(s));
}

void TrackingError::reset() {
  integral_.setZero();
  xt_.setZero();
  join_.stop();
  join_pending_ = join_.enabled();  // plan it again from the next state
}

}  // namespace tmpc
