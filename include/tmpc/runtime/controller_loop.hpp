// The on-board program's loop (thesis Figure 6.3) over a serial transport: each period
// read the newest state frame, pass it through the plausibility gate (state_gate.hpp),
// start the optimizer on the nominal state, compute the fallback, wait until the
// deadline (a fraction of the period), send the optimizer's law if it finished, else
// the LQR fallback, and record which. A link silent for more than the watchdog's
// periods (the artifact's link.watchdog_periods, default 10) triggers the safe command
// (the last feedforward with zero servo torques, or the hover input before any state),
// flagged in every control frame until valid states return. A state frame of a new
// session (the plant restarted) or a re-anchored track restarts the law from it: the
// nominal state, the integrals and the observer start at the measured state.
// Telemetry goes through a lock-free ring; human messages are returned, not logged,
// from the real-time thread. The clock and the optimizer are seams (ControllerLoopSeams)
// so that the timing logic is tested on a virtual clock.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "tmpc/io/protocol.hpp"
#include "tmpc/io/serial_port.hpp"
#include "tmpc/model/trajectory.hpp"
#include "tmpc/runtime/async_optimizer.hpp"
#include "tmpc/runtime/estimator_choice.hpp"
#include "tmpc/runtime/loop_clock.hpp"
#include "tmpc/runtime/realtime.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct ControllerLoopOptions {
  std::shared_ptr<const Trajectory> trajectory;  ///< what to fly (checked against the envelope first)
  std::string solver = "active-set";
  std::string solver_note;           ///< why this solver (--solver auto): the telemetry's first line
  std::string explicit_law;          ///< for solver "explicit"
  std::string tube_law;              ///< "" (the config's), "mayne" or "offset-free"
  EstimatorChoice estimator;         ///< the observer and the filter's adaptations (estimator_choice.hpp)
  double deadline_fraction = 0.8;    ///< the optimizer's result counts until this fraction of the period
  int silent_periods = 0;            ///< watchdog periods; 0: the artifact's link.watchdog_periods
  double duration_s = 0.0;           ///< stop after this long (0: when `stop` is set)
  bool reference_join = true;        ///< join the reference from the first state of each restart (reference_join.hpp)
  bool yaw_into_force = false;       ///< the mission's yaw is free: turned into the force (yaw_governor.hpp)
  RealTimeSettings realtime;
  std::string telemetry_csv;         ///< empty: no telemetry file
  std::uint32_t session = 0;         ///< this process's session id on the link; 0: drawn at start
  /// Wall-clock seconds per second of mission time (>= 1): the period and the deadline
  /// stretch by it, the mission's own times do not. 1 on a vehicle; more for a
  /// slow-motion hardware-in-the-loop run on a machine that cannot keep the period (a
  /// sanitizer build, a debugger), with the plant given the same scale.
  double time_scale = 1.0;
  /// Set once the loop is built (the artifact's law, the solver thread, the clock) and
  /// its first period starts: `tmpc hil` starts its plant then, so that the plant's
  /// mission does not begin with the controller's start-up as silence on the link.
  std::atomic<bool>* ready = nullptr;
};

struct ControllerLoopStats {
  long periods = 0, states = 0, optimizer_used = 0, late = 0, busy = 0, fallback_periods = 0;
  long safe_periods = 0, clipped_periods = 0, send_failures = 0;
  long softened_periods = 0;  ///< the hard QP was infeasible and the softened QP flew
  long reverted_periods = 0;  ///< of the fallback periods: the error past the reversion bound (revert_beyond)
  long skipped = 0;   ///< period boundaries the loop slept through (woken a period late or more)
  long restarts = 0;  ///< law restarts: first state, new sessions of the plant, re-anchored tracks
  long late_wakes = 0;  ///< periods the loop woke more than half a period late (the host's scheduling)
  int watchdog_periods = 0;
  double wake_latency_max_us = 0.0, wake_latency_p99_us = 0.0, period_jitter_max_us = 0.0;
  double solve_p50_us = 0.0, solve_max_us = 0.0;
  io::LinkCounts link;  ///< the decoder's and the state gate's counts
  std::uint32_t session = 0, peer_session = 0;
  std::string observer;  ///< the law's observer as flown: "none" (Mayne's law), "residual", "kalman" or "switched"
  unsigned long long telemetry_records = 0, telemetry_dropped = 0;
  RealTimeReport realtime;
};

/// Test seams: a clock other than CLOCK_MONOTONIC, an optimizer other than the solver
/// thread built from the options.
struct ControllerLoopSeams {
  LoopClock* clock = nullptr;
  Optimizer* optimizer = nullptr;
};

ControllerLoopStats run_controller_loop(const ControllerArtifact& a, io::Transport& link,
                                        const ControllerLoopOptions& o, const std::atomic<bool>& stop,
                                        const ControllerLoopSeams& seams = {});

}  // namespace tmpc
