// The loop clock and the virtual time line (see loop_clock.hpp).
#include "tmpc/runtime/loop_clock.hpp"

#include <stdexcept>

namespace tmpc {

LoopClock::LoopClock(double period_s) : period_ns_(static_cast<std::int64_t>(period_s * 1e9 + 0.5)) {
  if (!(period_s > 0.0) || period_s > 10.0 || period_ns_ < 1) {
    throw std::invalid_argument("loop clock: period must be in (0, 10] s");
  }
}

void LoopClock::start() {
  start_ns_ = next_ns_ = now_ns();
}

double LoopClock::wait() {
  next_ns_ += period_ns_;
  sleep_until_ns(next_ns_);
  const std::int64_t now = now_ns();
  if (woke_) last_period_us_ = 1e-3 * static_cast<double>(now - last_wake_ns_);
  last_wake_ns_ = now;
  woke_ = true;
  const std::int64_t late = now - next_ns_;
  const std::int64_t behind = late > 0 ? late / period_ns_ : 0;  // whole periods
  if (behind > 0) {
    next_ns_ += behind * period_ns_;
    skipped_ += static_cast<long>(behind);
  }
  return 1e-3 * static_cast<double>(late);
}

VirtualClock::VirtualClock(double period_s, std::int64_t start_ns) : LoopClock(period_s), now_(start_ns) { start(); }

void VirtualClock::sleep_until_ns(std::int64_t t_ns) {
  if (t_ns > now_) now_ = t_ns;
  now_ += latency_;
}

}  // namespace tmpc
