// Real-time set-up of the calling thread and its periodic clock (PREEMPT_RT practice):
// SCHED_FIFO priority, CPU affinity, mlockall and a prefaulted stack; periods by
// clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), with the wake-up latency and the
// actual period measured. Without privileges it runs anyway and reports, once, what
// it could not set (the caller logs it outside the real-time path).
#pragma once

#include <time.h>

#include <cstddef>
#include <string>
#include <vector>

namespace tmpc {

struct RealTimeSettings {
  int priority = 0;                        ///< SCHED_FIFO priority 1..99; 0: leave the scheduler alone
  int cpu = -1;                            ///< pin to this CPU; -1: no pinning
  bool lock_memory = true;                 ///< mlockall(MCL_CURRENT | MCL_FUTURE)
  std::size_t prefault_stack = 512 * 1024; ///< bytes of stack touched once
};

struct RealTimeReport {
  bool scheduler = false, affinity = false, memory_locked = false;
  std::vector<std::string> not_set;        ///< what could not be set, and why
};

/// Applies the settings to the calling thread. Never throws for missing privileges.
RealTimeReport apply_realtime(const RealTimeSettings& s);

class PeriodicClock {
 public:
  explicit PeriodicClock(double period_s);
  /// Sleeps until the next period boundary (absolute time: no drift). Returns the
  /// wake-up latency in us (actual minus planned wake-up, >= 0 up to clock noise).
  /// Woken a whole period late or more (the thread was not scheduled: a VM's steal
  /// time, a higher-priority hog), it does not run the missed boundaries back to back:
  /// the schedule moves to the last boundary before now and skipped() counts them.
  double wait();
  /// Period boundaries skipped after late wake-ups (each one a missed deadline).
  long skipped() const { return skipped_; }
  /// Time between the last two wake-ups (us); 0 before the second.
  double last_period_us() const { return last_period_us_; }
  /// Seconds since construction (CLOCK_MONOTONIC).
  double elapsed_s() const;
  /// The next planned wake-up (for a deadline inside the period, e.g. period start + d).
  const timespec& next_wakeup() const { return next_; }

 private:
  long period_ns_;
  timespec start_{}, next_{}, last_wake_{};
  double last_period_us_ = 0.0;
  long skipped_ = 0;
  bool woke_ = false;
};

/// t + ns as a normalized timespec.
timespec add_ns(timespec t, long ns);
/// (a - b) in us.
double diff_us(const timespec& a, const timespec& b);

}  // namespace tmpc
