// Telemetry: every record pushed reaches the file in order, or is counted as dropped
// when the writer stalls and the ring fills; the file is read back as the oracle.
#include <algorithm>
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

/// The tiltrotor's columns: 24 error states (20 measured), 4 inputs, the force estimate.
TelemetryLayout tiltrotor_layout() {
  TelemetryLayout l;
  for (int i = 0; i < 24; ++i) l.state_names.push_back("s" + std::to_string(i));
  l.input_names = {"f_r", "f_l", "tau_r", "tau_l"};
  l.measured = 20;
  l.disturbances = 3;
  return l;
}

TEST(Telemetry, ColumnsFollowTheLayout) {
  const std::string path = ::testing::TempDir() + "telemetry_layout.csv";
  TelemetryLayout small;
  small.state_names = {"p", "v", "int_p"};
  small.input_names = {"force"};
  small.measured = 2;
  {
    TelemetryWriter w(path, small);
    TelemetryRecord r;
    r.x[0] = 1.5;
    r.x[2] = -2.5;
    r.x[3] = 99.0;  // beyond the layout: not written
    r.u[0] = 0.25;
    w.push(r);
  }
  const std::vector<std::string> l = lines_of(path);
  ASSERT_EQ(l.size(), 2u);
  EXPECT_EQ(l[0].rfind("period,t,e_p,e_v,e_int_p,r_p,r_v,xbar_p,xbar_v,xbar_int_p,ubar_force,u_force,status,", 0), 0u)
      << l[0];
  EXPECT_EQ(l[0].find("dhat"), std::string::npos);
  auto columns = [](const std::string& s) { return std::count(s.begin(), s.end(), ',') + 1; };
  EXPECT_EQ(columns(l[1]), columns(l[0]));
  EXPECT_EQ(l[1].find(",99"), std::string::npos);
  EXPECT_NE(l[1].find(",1.5,0,-2.5,"), std::string::npos) << l[1];
  // A layout larger than a record is refused before anything is written.
  TelemetryLayout huge = small;
  huge.state_names.resize(kMaxStates + 1, "s");
  EXPECT_THROW(TelemetryWriter(path, huge), std::invalid_argument);
}

TEST(Telemetry, NoRecordIsLostFromAConcurrentProducer) {
  const std::string path = ::testing::TempDir() + "telemetry_all.csv";
  {
    TelemetryWriter w(path, tiltrotor_layout(), 1 << 12);
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
    TelemetryWriter w(path, tiltrotor_layout(), 64);
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
    TelemetryWriter w("/nonexistent/dir/t.csv", tiltrotor_layout());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/t.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace tmpc
