// The loop clock's period logic on the virtual time line: absolute boundaries (no
// drift), the wake-up latency, and boundaries slept through skipped, not replayed.
#include <gtest/gtest.h>

#include "tmpc/runtime/loop_clock.hpp"

namespace tmpc {
namespace {

TEST(LoopClock, WakesOnAbsoluteBoundariesWithoutDrift) {
  VirtualClock c(0.012, 1000);
  c.set_wake_latency(300000);  // every wake-up 0.3 ms late
  for (int k = 1; k <= 100; ++k) {
    EXPECT_NEAR(c.wait(), 300.0, 1e-9);
    EXPECT_EQ(c.next_wakeup_ns(), 1000 + k * 12000000LL);  // latency never accumulates
  }
  EXPECT_EQ(c.skipped(), 0);
  EXPECT_NEAR(c.last_period_us(), 12000.0, 1e-9);
  EXPECT_NEAR(c.elapsed_s(), 1.2003, 1e-12);
}

TEST(LoopClock, BoundariesSleptThroughAreSkipped) {
  VirtualClock c(0.01);
  c.wait();               // t = 10 ms
  c.advance(65000000);    // the thread is not scheduled for 65 ms
  const double late = c.wait();
  EXPECT_NEAR(late, 55000.0, 1e-9);  // against the boundary it missed (20 ms)
  EXPECT_EQ(c.skipped(), 5);         // 30, 40, 50, 60, 70 ms passed while it slept
  EXPECT_EQ(c.next_wakeup_ns(), 70000000);  // the last boundary before now (75 ms)
  c.wait();
  EXPECT_EQ(c.now_ns(), 80000000);  // the next one, not a burst of replayed periods
  EXPECT_EQ(c.skipped(), 5);
}

TEST(LoopClock, RefusesABadPeriod) {
  EXPECT_THROW(VirtualClock(0.0), std::invalid_argument);
  EXPECT_THROW(VirtualClock(11.0), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
