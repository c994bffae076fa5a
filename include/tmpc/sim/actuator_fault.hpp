// Actuator faults of a scenario, applied inside the plant to the input it is sent (the
// controller never learns of them): per input channel i and time window [start, end),
//   efficiency  u_i <- factor u_i          (a rotor that lost thrust, a weak servo)
//   bias        u_i <- u_i + value         (a miscalibrated ESC or servo driver)
//   stuck       u_i <- u_i(start)          (a jammed channel: held at the first value
//                                           sent at or after `start`)
// Faults on one channel compose in the order given. The fault acts over a whole plant
// period, like the input (zero-order hold); a period counts as faulty when it starts
// inside the window. `with_actuator_faults` wraps any plant (el, mujoco, linear).
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/sim/plant.hpp"

namespace tmpc {

struct ActuatorFault {
  enum class Kind { Efficiency, Bias, Stuck };
  Kind kind = Kind::Efficiency;
  int input = 0;                                                      ///< channel, 0-based
  double factor = 1.0;                                                ///< efficiency
  double value = 0.0;                                                 ///< bias, input's units
  double start = 0.0, end = std::numeric_limits<double>::infinity();  ///< s
};

/// The input the plant applies at time t for the commanded u (in place into `applied`,
/// sized like u; no allocation). Keeps the stuck channels' held values between calls.
class ActuatorFaults {
 public:
  /// Throws std::invalid_argument naming the fault (faults[k]) for a channel outside
  /// [0, inputs), a non-finite or negative factor, a non-finite bias, or end <= start.
  ActuatorFaults(std::vector<ActuatorFault> faults, int inputs);
  void apply(double t, const Eigen::VectorXd& u, Eigen::VectorXd& applied);

 private:
  std::vector<ActuatorFault> faults_;
  std::vector<double> held_;     ///< per fault: the stuck value
  std::vector<char> has_held_;   ///< per fault: held_ set
};

/// `plant` with the faults between its input and the command it is sent.
std::unique_ptr<Plant> with_actuator_faults(std::unique_ptr<Plant> plant, std::vector<ActuatorFault> faults);

}  // namespace tmpc
