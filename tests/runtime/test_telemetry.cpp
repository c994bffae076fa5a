// Telemetry: every record pushed reaches the file in order, or is counted as dropped
// when the writer stalls and the ring fills; the file is read back as the oracle.
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "tmpc/runtime/telemetry.hpp"

namespace tmpc {
namespace {

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> v;
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

TEST(Telemetry, RingIsFifoAndRefusesWhenFull) {
  SpscRing<int> ring(5);
  EXPECT_EQ(ring.capacity(), 8u);
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(ring.push(i));
  EXPECT_FALSE(ring.push(99));
  int v = -1;
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(ring.pop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(ring.pop(v));
}

TEST(Telemetry, NoRecordIsLostFromAConcurrentProducer) {
  const std::string path = ::testing::TempDir() + "telemetry_all.csv";
  {
    TelemetryWriter w(path, 1 << 12);
    std::thread producer([&] {
      TelemetryRecord r;
      for (std::uint64_t k = 0; k < 50000; ++k) {
        r.period = k;
        r.t = 0.012 * static_cast<double>(k);
        r.u[0] = static_cast<double>(k);
        while (!w.push(r)) std::this_thread::yield();  // a test producer may retry; the loop never does
      }
    });
    producer.join();
  }
  const std::vector<std::string> l = lines_of(path);
  ASSERT_EQ(l.size(), 50001u);  // header + every record
  for (std::size_t k = 1; k < l.size(); k += 997) {
    EXPECT_EQ(l[k].substr(0, l[k].find(',')), std::to_string(k - 1));
  }
}

TEST(Telemetry, OverflowIsCountedExactly) {
  const std::string path = ::testing::TempDir() + "telemetry_overflow.csv";
  std::uint64_t pushed = 0, dropped = 0;
  {
    TelemetryWriter w(path, 64);
    w.pause_writer(true);  // a stalled disk
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    TelemetryRecord r;
    for (int k = 0; k < 200; ++k) {
      r.period = static_cast<std::uint64_t>(k);
      w.push(r);
    }
    pushed = w.pushed();
    dropped = w.dropped();
    EXPECT_EQ(dropped, 200u - 64u);
    w.pause_writer(false);
  }
  EXPECT_EQ(pushed, 200u);
  EXPECT_EQ(lines_of(path).size(), 1u + pushed - dropped);
}

TEST(Telemetry, UnwritablePathIsAClearError) {
  try {
    TelemetryWriter w("/nonexistent/dir/t.csv");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/t.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace tmpc
