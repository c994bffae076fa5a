// The on-board program's loop (thesis Figure 6.3) over a serial transport: each period
// read the newest valid state frame, start the optimizer on the nominal state, compute
// the fallback, wait until the deadline (a fraction of the period), send the
// optimizer's law if it finished, else the LQR fallback, and record which. A link
// silent for more than `silent_periods` periods triggers the safe command (the
// feedforward with zero servo torques, or hover before any state) flagged in every
// control frame until valid states return. Telemetry goes through a lock-free ring;
// human messages are returned, not logged, from the real-time thread.
#pragma once

#include <atomic>
#include <string>

#include "tmpc/io/protocol.hpp"
#include "tmpc/io/serial_port.hpp"
#include "tmpc/runtime/realtime.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct ControllerLoopOptions {
  std::string solver = "admm";
  std::string explicit_law;          ///< for solver "explicit"
  std::string tube_law;              ///< "" (the config's), "mayne" or "offset-free"
  double deadline_fraction = 0.8;    ///< the optimizer's result counts until this fraction of the period
  int silent_periods = 10;           ///< watchdog: periods without a valid state before the safe command
  double duration_s = 0.0;           ///< stop after this long (0: when `stop` is set)
  RealTimeSettings realtime;
  std::string telemetry_csv;         ///< empty: no telemetry file
};

struct ControllerLoopStats {
  long periods = 0, states = 0, optimizer_used = 0, late = 0, busy = 0, fallback_periods = 0;
  long safe_periods = 0, clipped_periods = 0, send_failures = 0;
  long skipped = 0;  ///< period boundaries the loop slept through (woken a period late or more)
  double wake_latency_max_us = 0.0, wake_latency_p99_us = 0.0, period_jitter_max_us = 0.0;
  double solve_p50_us = 0.0, solve_max_us = 0.0;
  io::DecoderStats link;
  unsigned long long telemetry_records = 0, telemetry_dropped = 0;
  RealTimeReport realtime;
};

ControllerLoopStats run_controller_loop(const ControllerArtifact& a, io::Transport& link,
                                        const ControllerLoopOptions& o, const std::atomic<bool>& stop);

}  // namespace tmpc
