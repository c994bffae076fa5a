// The periodic clock of a real-time loop, with the time line it runs on as a seam:
// PeriodicClock (realtime.hpp) sleeps on CLOCK_MONOTONIC, VirtualClock advances only
// when the loop sleeps or a test says so, so that the loop's timing logic (deadline,
// late and busy periods, skipped boundaries, the watchdog) runs deterministically on
// any machine.
//   wait(): sleep until the next boundary start + k T (absolute: no drift); woken a
//   whole period late or more, the schedule moves to the last boundary before now and
//   skipped() counts the boundaries slept through instead of running them back to back.
#pragma once

#include <cstdint>

namespace tmpc {

class LoopClock {
 public:
  /// Throws std::invalid_argument unless 0 < period_s <= 10.
  explicit LoopClock(double period_s);
  virtual ~LoopClock() = default;
  LoopClock(const LoopClock&) = delete;
  LoopClock& operator=(const LoopClock&) = delete;

  /// Sleeps until the next period boundary; returns the wake-up latency in us (actual
  /// minus planned wake-up, >= 0 up to clock noise).
  double wait();
  /// Period boundaries skipped after late wake-ups (each one a missed deadline).
  long skipped() const { return skipped_; }
  /// Time between the last two wake-ups (us); 0 before the second.
  double last_period_us() const { return last_period_us_; }
  /// Seconds since start.
  double elapsed_s() const { return 1e-9 * static_cast<double>(now_ns() - start_ns_); }
  /// The planned wake-up of the current period (after wait(): this period's boundary).
  std::int64_t next_wakeup_ns() const { return next_ns_; }
  std::int64_t period_ns() const { return period_ns_; }

  /// The clock's time line, ns.
  virtual std::int64_t now_ns() const = 0;
  /// Sleep until `t_ns` on this time line (returns at once if it has passed).
  virtual void sleep_until_ns(std::int64_t t_ns) = 0;

 protected:
  /// Derived constructors call this once their time line works.
  void start();

 private:
  std::int64_t period_ns_;
  std::int64_t start_ns_ = 0, next_ns_ = 0, last_wake_ns_ = 0;
  double last_period_us_ = 0.0;
  long skipped_ = 0;
  bool woke_ = false;
};

/// A time line that moves only when told: sleep_until() jumps to the wake-up time
/// plus `wake_latency_ns`, advance() stands for work or a stall of the calling thread.
class VirtualClock final : public LoopClock {
 public:
  explicit VirtualClock(double period_s, std::int64_t start_ns = 0);
  std::int64_t now_ns() const override { return now_; }
  void sleep_until_ns(std::int64_t t_ns) override;
  void advance(std::int64_t ns) { now_ += ns; }
  /// Every sleep overshoots by this much (a scheduler's latency).
  void set_wake_latency(std::int64_t ns) { latency_ = ns; }

 private:
  std::int64_t now_;
  std::int64_t latency_ = 0;
};

}  // namespace tmpc
