// The estimator's flags (see estimator_flags.hpp).
#include "estimator_flags.hpp"

namespace tmpc::cli {

void add_estimator_flags(CLI::App* sub, EstimatorChoice& e) {
  sub->add_option("--observer", e.observer, "offset-free observer: residual, kalman or switched (default: the artifact's)")
      ->check(CLI::IsMember({"residual", "kalman", "switched"}));
  sub->add_option("--observer-gain", e.observer_gain, "offset-free observer gain beta in (0, 1] (default: the artifact's)")
      ->check(CLI::Range(1e-6, 1.0));
  sub->add_flag("--fixed-filter-gain", e.fixed_filter_gain,
                "the Kalman filter's design gain at every noise level (default: the gain for the noise monitor's level, "
                "runtime/filter_gain_schedule.hpp)");
  sub->add_flag("--no-innovation-gate", e.no_innovation_gate,
                "the Kalman filter takes every measurement (default: a position or angle whose innovation exceeds 20 of its "
                "standard deviations is a glitch, replaced by the filter's prediction; runtime/tube_controller.hpp)");
  CLI::Option* no_steps = sub->add_flag("--no-step-detection", e.no_step_detection,
                                        "the Kalman filter keeps its gains at a disturbance step (default: a step detected "
                                        "in its innovations, a rotor's thrust loss, re-opens its disturbance covariance; "
                                        "runtime/tube_controller.hpp)");
  sub->add_flag_callback(
         "--step-keeps-lift", [&e] { e.step_reopens_lift = false; },
         "a disturbance step keeps the vertical force's steady covariance (default: a step the filter's innovations do "
         "not classify as a horizontal force, a rotor's thrust loss, re-opens the lift too; runtime/tube_controller.hpp)")
      ->excludes(no_steps);
  sub->add_flag_callback(
         "--no-actuator-step", [&e] { e.step_corrects_input = false; },
         "a disturbance step the actuators explain is left to the re-opened gains (default: the filter's prediction "
         "takes that step's effect since its onset, read from the innovations; runtime/tube_controller.hpp)")
      ->excludes(no_steps);
  sub->add_flag_callback(
         "--reopen-late-steps", [&e] { e.late_step_keeps_gain = false; },
         "a disturbance step detected older than the detection window (0.24 s) re-opens the filter's gains too "
         "(default: it is left to the steady gain, which has been reading it; runtime/tube_controller.hpp)")
      ->excludes(no_steps);
  sub->add_option("--revert-beyond", e.revert_beyond,
                  "past this many times a state's bound (> 1), the tube gain's unconstrained law flies until every state is "
                  "back within --revert-within times its bound; 0: never (default: the artifact's tube_law.revert_beyond; "
                  "runtime/tube_controller.hpp)")
      ->check(CLI::Range(0.0, 1e6));
  sub->add_option("--revert-within", e.revert_within,
                  "the MPC law again once every state is within this many times its bound (default: the artifact's "
                  "tube_law.revert_within)")
      ->check(CLI::Range(1.0, 1e6));
}

}  // namespace tmpc::cli
