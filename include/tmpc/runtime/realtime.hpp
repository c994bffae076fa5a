// Real-time set-up of the calling thread and its periodic clock (PREEMPT_RT practice):
// SCHED_FIFO priority, CPU affinity, mlockall and a prefaulted stack; periods by
// clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) (loop_clock.hpp for the period logic). Without privileges it runs anyway and reports, once, what
// it could not set (the caller logs it outside the real-time path).
#pragma once

#include <time.h>

#include <cstddef>
#include <string>
#include <vector>

#include "tmpc/runtime/loop_clock.hpp"

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

/// The loop clock on CLOCK_MONOTONIC (clock_nanosleep, TIMER_ABSTIME).
class PeriodicClock final : public LoopClock {
 public:
  explicit PeriodicClock(double period_s);
  std::int64_t now_ns() const override;
  void sleep_until_ns(std::int64_t t_ns) override;
  /// The planned wake-up of the current period as a timespec.
  timespec next_wakeup() const;
};

/// t + ns as a normalized timespec.
timespec add_ns(timespec t, long ns);
/// (a - b) in us.
double diff_us(const timespec& a, const timespec& b);

}  // namespace tmpc
