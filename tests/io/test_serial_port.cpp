// Frames over a pseudo-terminal pair opened like a serial port: every frame arrives,
// in both directions; garbage on the line is counted and dropped; bad settings are
// clear errors.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "tmpc/io/protocol.hpp"
#include "tmpc/io/serial_port.hpp"

namespace tmpc::io {
namespace {

// Read until `want` frames were accepted or 2 s passed.
int pump(Transport& t, Decoder& d, int want) {
  std::uint8_t buf[512];
  int got = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (got < want && std::chrono::steady_clock::now() < end) {
    const long n = t.read_some(buf, sizeof(buf));
    if (n < 0) break;
    for (long i = 0; i < n; ++i) got += d.push(buf[i]);
    if (n == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return got;
}

TEST(SerialPort, FramesCrossAPseudoTerminalBothWays) {
  PtyPair pty = open_pty_pair();
  SerialOpenReport rep;
  auto port = open_serial(pty.slave_path, 921600, &rep);
  EXPECT_FALSE(rep.low_latency && !rep.note.empty());
  std::vector<std::uint8_t> bytes;
  Decoder at_controller(state_decoder_settings(20));
  for (std::uint32_t k = 1; k <= 200; ++k) {
    StateFrame s;
    s.session = 3;
    s.n = 20;
    s.seq = k;
    s.time = 0.012 * k;
    s.x[0] = 0.5 + 0.001 * k;
    encode(s, bytes);
    ASSERT_TRUE(pty.master->write_all(bytes.data(), bytes.size()));
    if (k % 50 == 0) ASSERT_EQ(pump(*port, at_controller, 50), 50);
  }
  EXPECT_EQ(at_controller.counts().accepted, 200);
  EXPECT_EQ(at_controller.state().seq, 200u);
  EXPECT_DOUBLE_EQ(at_controller.state().x[0], 0.7);
  // Garbage, then a valid frame: the garbage is counted, the frame accepted.
  const std::uint8_t junk[] = {1, 2, 3, 0, 0x55, 0x66, 0};
  ASSERT_TRUE(pty.master->write_all(junk, sizeof(junk)));
  StateFrame s;
  s.session = 3;
  s.n = 20;
  s.seq = 201;
  encode(s, bytes);
  ASSERT_TRUE(pty.master->write_all(bytes.data(), bytes.size()));
  EXPECT_EQ(pump(*port, at_controller, 1), 1);
  EXPECT_GE(at_controller.counts().rejected_total(), 2);
  // And back: control frames to the plant side.
  Decoder at_plant(control_decoder_settings(4));
  ControlFrame c;
  c.session = 4;
  c.n = 4;
  c.seq = 7;
  c.u = {11.7, 11.8, 0.001, -0.002};
  c.flags = ControlFrame::kFallback;
  encode(c, bytes);
  ASSERT_TRUE(port->write_all(bytes.data(), bytes.size()));
  ASSERT_EQ(pump(*pty.master, at_plant, 1), 1);
  EXPECT_EQ(at_plant.control().flags, ControlFrame::kFallback);
  EXPECT_DOUBLE_EQ(at_plant.control().u[1], 11.8);
}

TEST(SerialPort, BadDeviceOrBaudIsAClearError) {
  try {
    open_serial("/dev/does-not-exist-tmpc", 921600);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/does-not-exist-tmpc"), std::string::npos);
  }
  PtyPair pty = open_pty_pair();
  try {
    open_serial(pty.slave_path, 12345);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported baud 12345"), std::string::npos);
  }
  EXPECT_THROW(open_serial("/dev/null", 921600), std::runtime_error);  // not a terminal
}

}  // namespace
}  // namespace tmpc::io
