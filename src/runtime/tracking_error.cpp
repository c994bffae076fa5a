// Tracking error (see tracking_error.hpp).
#include "tmpc/runtime/tracking_error.hpp"

#include <cmath>
#include <stdexcept>

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
  if (yaw_frame_) {
    const double a = x_r(yaw_row_) - yaw_, c = std::cos(a), s = std::sin(a);
    for (const int* rows : {pos_, vel_}) {
      const double ex = e(rows[0]), ey = e(rows[1]);
      e(rows[0]) = c * ex + s * ey;
      e(rows[1]) = -s * ex + c * ey;
    }
  }
}

void TrackingError::set_yaw_frame(double yaw) {
  int np = 0, nv = 0;
  yaw_row_ = -1;
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    const int r = static_cast<int>(i);
    if (kinds_[i] == StateKind::Yaw && yaw_row_ < 0) yaw_row_ = r;
    if (kinds_[i] == StateKind::Position && np < 2) pos_[np++] = r;
    if (kinds_[i] == StateKind::Velocity && nv < 2) vel_[nv++] = r;
  }
  if (yaw_row_ < 0 || np < 2 || nv < 2) {
    throw std::invalid_argument("tracking error: the yaw frame needs a yaw state and two position and velocity states");
  }
  yaw_ = yaw;
  yaw_frame_ = true;
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
