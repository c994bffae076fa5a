// A flight's estimator choice over the artifact's design (see estimator_choice.hpp).
#include "tmpc/runtime/estimator_choice.hpp"

#include <stdexcept>

namespace tmpc {

TubeControllerOptions flight_law_options(const ControllerArtifact& a, const std::string& tube_law,
                                         const EstimatorChoice& e) {
  if (e.no_step_detection && !e.step_reopens_lift) {
    throw std::invalid_argument("estimator: keeping the lift at a step needs the step detection (both were asked)");
  }
  if (e.no_step_detection && !e.step_corrects_input) {
    throw std::invalid_argument("estimator: leaving an actuator's step to the gains needs the step detection (both were asked)");
  }
  if (e.no_step_detection && !e.late_step_keeps_gain) {
    throw std::invalid_argument("estimator: re-opening the gains at a late step needs the step detection (both were asked)");
  }
  TubeControllerOptions o = tube_law_options(a, tube_law, e.observer_gain, e.observer);
  o.adaptive_filter_gain = !e.fixed_filter_gain;
  o.innovation_gate = !e.no_innovation_gate;
  o.step_detection = !e.no_step_detection;
  o.step_reopens_lift = e.step_reopens_lift;
  o.step_corrects_input = e.step_corrects_input;
  o.late_step_keeps_gain = e.late_step_keeps_gain;
  if (e.revert_beyond >= 0.0) o.revert_beyond = e.revert_beyond;
  if (e.revert_within >= 0.0) o.revert_within = e.revert_within;
  o.validate();
  return o;
}

}  // namespace tmpc
