// Real-time set-up reports what it could not set instead of failing; the periodic
// clock wakes at absolute period boundaries (no drift).
#include <cmath>
#include <ctime>

#include <gtest/gtest.h>

#include "tmpc/runtime/realtime.hpp"

namespace tmpc {
namespace {

TEST(RealTime, SettingsThatCannotBeAppliedAreReportedNotFatal) {
  RealTimeSettings s;
  s.priority = 80;
  s.cpu = 0;
  s.lock_memory = false;  // keep the test process ordinary
  const RealTimeReport r = apply_realtime(s);
  bool said_scheduler = false, said_affinity = false;
  for (const std::string& m : r.not_set) {
    said_scheduler |= m.find("SCHED_FIFO") != std::string::npos;
    said_affinity |= m.find("affinity") != std::string::npos;
  }
  EXPECT_NE(r.scheduler, said_scheduler);  // set, or said why not
  EXPECT_NE(r.affinity, said_affinity);
  RealTimeSettings bad;
  bad.cpu = 100000;  // no such CPU: reported
  bad.lock_memory = false;
  const RealTimeReport rb = apply_realtime(bad);
  EXPECT_FALSE(rb.affinity);
  ASSERT_FALSE(rb.not_set.empty());
  EXPECT_NE(rb.not_set.front().find("affinity"), std::string::npos);
}

TEST(RealTime, PeriodicClockHasNoDrift) {
  PeriodicClock c(0.002);
  for (int k = 0; k < 50; ++k) EXPECT_GE(c.wait(), -50.0);  // never early beyond clock noise
  // 50 periods of 2 ms: absolute wake-ups keep the elapsed time at 100 ms plus one
  // latency, and plus the boundaries skipped when the machine stalled a whole period
  // (a VM's steal time; a relative sleep would add every wake-up's latency instead).
  EXPECT_GE(c.elapsed_s(), 0.1);
  EXPECT_LT(c.elapsed_s(), 0.002 * (50 + static_cast<double>(c.skipped())) + 0.05) << c.skipped() << " skipped";
  EXPECT_GT(c.last_period_us(), 0.0);
  EXPECT_THROW(PeriodicClock(0.0), std::invalid_argument);
}

TEST(RealTime, PeriodicClockSkipsTheBoundariesItSleptThrough) {
  const long period_ns = 10'000'000;  // 10 ms
  PeriodicClock c(1e-2);
  c.wait();
  const timespec planned = c.next_wakeup();
  // The thread is "not scheduled" for 65 ms: six boundaries pass.
  timespec stall = add_ns(planned, 65'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &stall, nullptr) == EINTR) {
  }
  const double late = c.wait();
  EXPECT_GE(late, 55'000.0);  // against the first boundary it missed
  EXPECT_GE(c.skipped(), 5);  // 6 here (more if this machine stalled too)
  // The schedule stays on the grid of boundaries and moves past them: the next wait
  // sleeps to the first boundary after now instead of returning at once.
  const long since = static_cast<long>(std::llround(diff_us(c.next_wakeup(), planned) * 1e3));
  EXPECT_EQ(since % period_ns, 0);
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  EXPECT_LE(diff_us(c.next_wakeup(), now), 0.0);  // the last boundary at or before now
  const long skipped = c.skipped();
  c.wait();
  EXPECT_GT(diff_us(c.next_wakeup(), stall), 0.0);
  EXPECT_LE(c.skipped() - skipped, 1);  // a normal wait (one more only if this machine stalled)
}

}  // namespace
}  // namespace tmpc
