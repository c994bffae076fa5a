// What one flight chooses of the offset-free law's estimator over the artifact's design:
// the observer (residual, Kalman filter or switched), its gain, and the filter's
// adaptations (the gain schedule, the glitch gate, the step detection and whether a
// step re-opens the lift), and the law's reversion to the tube gain's unconstrained law
// past the model's region (tube_controller.hpp revert_beyond). The simulator (`tmpc simulate`) and the serial loop
// (`tmpc controller`, `tmpc hil`) take the same choice, so that a flight simulated with
// one estimator is flown on the link with that one.
#pragma once

#include <string>

#include "tmpc/runtime/tube_controller.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct EstimatorChoice {
  std::string observer;             ///< "" (the artifact's), "residual", "kalman" or "switched"
  double observer_gain = 0.0;       ///< > 0: overrides the artifact's beta
  bool fixed_filter_gain = false;   ///< the Kalman filter: the design's gain at every noise level
  bool no_innovation_gate = false;  ///< the Kalman filter: take every measurement (no glitch gate)
  bool no_step_detection = false;   ///< the Kalman filter keeps its gains at a disturbance step
  bool step_reopens_lift = true;    ///< a step not classified as horizontal re-opens the vertical force too
  bool step_corrects_input = true;  ///< a step the actuators explain corrects the filter's prediction
  bool late_step_keeps_gain = true;  ///< a step older than the detection window keeps the steady gain
  double revert_beyond = -1.0;  ///< the reversion's enter bound (tube_controller.hpp): < 0 the artifact's, 0 off
  double revert_within = -1.0;  ///< its leave bound: < 0 the artifact's
};

/// The law's options: the artifact's tube law overridden by `tube_law` ("", "mayne" or
/// "offset-free") and the estimator by `e`. Throws std::invalid_argument naming what
/// the artifact cannot give (tube_law_options) or a step option without step detection.
TubeControllerOptions flight_law_options(const ControllerArtifact& a, const std::string& tube_law,
                                         const EstimatorChoice& e);

}  // namespace tmpc
