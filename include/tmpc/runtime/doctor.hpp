// `tmpc doctor`: is this board set up for the real-time loop? Each finding says what
// was found and what to do about it: the kernel's preemption model (PREEMPT_RT), the
// real-time throttling, the CPU frequency governors, isolated CPUs, the memlock and
// rtprio limits, the serial device (existence, permissions, a USB adapter's latency
// timer), and a cyclictest-style wake-up latency run judged against the controller's
// period and deadline. The host checks read procfs and sysfs under roots given in
// DoctorEnvironment, so they are tested on fake trees.
#pragma once

#include <string>
#include <vector>

namespace tmpc {

enum class Severity { Ok, Info, Warn, Fail };
const char* to_string(Severity s);

struct Finding {
  std::string check;   ///< e.g. "kernel", "rt throttling"
  Severity severity = Severity::Info;
  std::string found;   ///< what was read
  std::string advice;  ///< what to do (empty when Ok)
};

struct DoctorEnvironment {
  std::string proc = "/proc";
  std::string sys = "/sys";
  bool privileged = false;  ///< running as root (CAP_SYS_NICE, CAP_IPC_LOCK): limits do not apply
};

/// A wake-up latency run: a thread at the requested priority and CPU sleeping to
/// absolute times `interval` apart (clock_nanosleep, CLOCK_MONOTONIC), latency = actual
/// minus planned wake-up.
struct LatencyRun {
  int samples = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;
  bool realtime = false;  ///< the thread got SCHED_FIFO
  std::string note;       ///< what could not be set
};

struct DoctorOptions {
  DoctorEnvironment env;
  std::string port;                ///< serial device to check; empty: not checked
  int rt_priority = 80;            ///< the controller's SCHED_FIFO priority
  int cpu = -1;                    ///< the controller's CPU (-1: not pinned)
  double period_s = 0.012;         ///< the controller's period (the artifact's sample time)
  double deadline_fraction = 0.8;  ///< the optimizer's budget within the period
  double solve_p99_us = -1.0;      ///< the chosen solver's calibrated p99 (< 0: not known)
};

/// The procfs/sysfs checks and the serial device's (no latency run).
std::vector<Finding> check_host(const DoctorOptions& o);

/// Measures the wake-up latency for `seconds` at `interval_s`.
LatencyRun measure_wakeup_latency(double seconds, double interval_s, int priority, int cpu);

/// Fail when the p99 latency plus the solve p99 exceeds the optimizer's budget (the
/// loop would miss its deadline regularly); Warn when only the maximum does (rare
/// late periods, flown by the LQR fallback) or the loop could not get SCHED_FIFO; Ok
/// otherwise.
Finding latency_verdict(const LatencyRun& r, const DoctorOptions& o);

/// True when no finding is a Fail (the exit status of `tmpc doctor`).
bool can_run(const std::vector<Finding>& findings);

}  // namespace tmpc
