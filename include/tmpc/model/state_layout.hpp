// What each error state measures, so that code outside the vehicle model can treat a
// state by its kind: the plausibility gates and their defaults (per group), the yaw's
// wrap-around, the sensor-noise groups. The tiltrotor's 24 error states (DESIGN.md 3):
//   x y z | phi theta psi gamma_1 gamma_2 alpha_r alpha_l | 3 velocities | 7 rates | 4 integrals
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tmpc {

/// Largest state and input counts a design may have: every state (measured and
/// integral) fits a telemetry record, every measured one a serial state frame.
constexpr int kMaxStates = 48;
constexpr int kMaxInputs = 16;

enum class StateKind : std::uint8_t { Position = 0, Angle = 1, Yaw = 2, Velocity = 3, AngularRate = 4, Integral = 5 };
const char* to_string(StateKind k);
/// The kind named by to_string(); throws std::invalid_argument for another name.
StateKind state_kind_from_string(const std::string& s);

/// Groups of the plausibility gates: positions, angles (the yaw included), velocities, rates.
enum class StateGroup : std::uint8_t { Position = 0, Angle = 1, Velocity = 2, AngularRate = 3, None = 4 };
StateGroup group_of(StateKind k);

/// Kinds of the tiltrotor's 24 error states in the order of DESIGN.md 3.
std::vector<StateKind> tiltrotor_state_kinds();

}  // namespace tmpc
