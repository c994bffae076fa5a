// Real-time set-up reports what it could not set instead of failing; the periodic
// clock wakes at absolute period boundaries (no drift).
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
  // 50 periods of 2 ms: absolute wake-ups keep the elapsed time at 100 ms (plus one latency).
  EXPECT_GE(c.elapsed_s(), 0.1);
  EXPECT_LT(c.elapsed_s(), 0.1 + 0.05);
  EXPECT_GT(c.last_period_us(), 0.0);
  EXPECT_THROW(PeriodicClock(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
