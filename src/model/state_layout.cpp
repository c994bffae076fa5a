// State kinds (see state_layout.hpp).
#include "tmpc/model/state_layout.hpp"

#include <stdexcept>

namespace tmpc {

const char* to_string(StateKind k) {
  switch (k) {
    case StateKind::Position: return "position";
    case StateKind::Angle: return "angle";
    case StateKind::Yaw: return "yaw";
    case StateKind::Velocity: return "velocity";
    case StateKind::AngularRate: return "angular_rate";
    case StateKind::Integral: return "integral";
  }
  return "?";
}

StateKind state_kind_from_string(const std::string& s) {
  for (int k = 0; k <= static_cast<int>(StateKind::Integral); ++k) {
    if (s == to_string(static_cast<StateKind>(k))) return static_cast<StateKind>(k);
  }
  throw std::invalid_argument("unknown state kind '" + s +
                              "' (expected position, angle, yaw, velocity, angular_rate or integral)");
}

StateGroup group_of(StateKind k) {
  switch (k) {
    case StateKind::Position: return StateGroup::Position;
    case StateKind::Angle:
    case StateKind::Yaw: return StateGroup::Angle;
    case StateKind::Velocity: return StateGroup::Velocity;
    case StateKind::AngularRate: return StateGroup::AngularRate;
    case StateKind::Integral: return StateGroup::None;
  }
  return StateGroup::None;
}

std::vector<StateKind> tiltrotor_state_kinds() {
  std::vector<StateKind> k;
  for (int i = 0; i < 3; ++i) k.push_back(StateKind::Position);
  k.push_back(StateKind::Angle);  // phi
  k.push_back(StateKind::Angle);  // theta
  k.push_back(StateKind::Yaw);    // psi
  for (int i = 0; i < 4; ++i) k.push_back(StateKind::Angle);  // gamma_1, gamma_2, alpha_r, alpha_l
  for (int i = 0; i < 3; ++i) k.push_back(StateKind::Velocity);
  for (int i = 0; i < 7; ++i) k.push_back(StateKind::AngularRate);
  for (int i = 0; i < 4; ++i) k.push_back(StateKind::Integral);
  return k;
}

}  // namespace tmpc
