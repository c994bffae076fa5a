// The on-board loop over a pseudo-terminal, the test playing the plant: valid states
// get the tube law; a silent link triggers the safe command, flagged in every control
// frame until states return; garbage frames are counted, never fatal; every period
// leaves a telemetry record.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/controller_loop.hpp"

namespace tmpc {
namespace {

/// One run of the scenario: the plant side sends 30 periods of states, is silent for
/// 25, sends 30 more; the control frames it gets back, counted by their flags.
struct SilentLinkRun {
  ControllerLoopStats st;
  int got = 0, safe_while_talking = 0, safe_while_silent = 0, normal_while_silent = 0;
  std::string telemetry_csv;
};

SilentLinkRun silent_link_run(const ControllerArtifact& a, const HelixTrajectory& traj) {
  SilentLinkRun run;
  io::PtyPair pty = io::open_pty_pair();
  auto port = io::open_serial(pty.slave_path);
  ControllerLoopOptions o;
  o.silent_periods = 5;
  o.telemetry_csv = run.telemetry_csv = ::testing::TempDir() + "loop_telemetry.csv";
  std::atomic<bool> stop{false};
  std::thread loop([&] { run.st = run_controller_loop(a, *port, o, stop); });

  io::Decoder controls(io::FrameType::Control);
  std::vector<std::uint8_t> bytes;
  std::uint8_t buf[512];
  std::uint32_t seq = 0;
  const auto period = std::chrono::milliseconds(12);
  auto next = std::chrono::steady_clock::now();
  for (int k = 0; k < 85; ++k) {
    const bool silent = k >= 30 && k < 55;
    if (!silent) {
      const double t = 0.012 * k;
      const ReferencePoint r = traj.at(t);
      io::StateFrame s;
      s.seq = ++seq;
      s.time = t;
      for (int i = 0; i < 10; ++i) {
        s.x[static_cast<std::size_t>(i)] = r.q(i);
        s.x[static_cast<std::size_t>(10 + i)] = r.qd(i);
      }
      io::encode(s, bytes);
      EXPECT_TRUE(pty.master->write_all(bytes.data(), bytes.size()));
      if (k == 70) {  // garbage on the line
        const std::uint8_t junk[] = {9, 9, 9, 0};
        pty.master->write_all(junk, sizeof(junk));
      }
    }
    next += period;
    std::this_thread::sleep_until(next);
    for (long n; (n = pty.master->read_some(buf, sizeof(buf))) > 0;) {
      for (long i = 0; i < n; ++i) {
        if (!controls.push(buf[i])) continue;
        ++run.got;
        const bool safe = controls.control().flags & io::ControlFrame::kSafe;
        if (k >= 40 && k < 55) {  // well after the link went silent
          run.safe_while_silent += safe;
          run.normal_while_silent += !safe;
        }
        if ((k >= 10 && k < 30) || k >= 65) run.safe_while_talking += safe;
      }
    }
  }
  stop.store(true);
  loop.join();
  return run;
}

TEST(ControllerLoop, SilentLinkTriggersTheSafeCommandUntilStatesReturn) {
  const ControllerArtifact a = make_artifact(test::quick_design());
  const Config cfg = test::quick_config();
  const TiltrotorModel model(cfg.vehicle);
  const HelixTrajectory traj(cfg.reference, model);
  // The counts below assume the controller thread ran when it asked to. On a shared
  // VM the host can stall it for tens of ms (steal time; seen: 99 ms), which shifts
  // what "silent" means to it: such a run is repeated, up to three times.
  SilentLinkRun run;
  for (int attempt = 1; attempt <= 3; ++attempt) {
    run = silent_link_run(a, traj);
    if (run.st.wake_latency_max_us < 6000.0) break;
    std::printf("attempt %d: the controller thread woke up to %.1f ms late (machine stall); again\n", attempt,
                run.st.wake_latency_max_us / 1e3);
  }
  if (run.st.wake_latency_max_us >= 6000.0) {
    GTEST_SKIP() << "the machine stalled the controller thread in all three runs (last: "
                 << run.st.wake_latency_max_us / 1e3 << " ms late): its timing cannot be judged here";
  }
  const ControllerLoopStats& st = run.st;
  EXPECT_GT(run.got, 60);
  EXPECT_GT(run.safe_while_silent, 10);
  EXPECT_EQ(run.normal_while_silent, 0);
  EXPECT_EQ(run.safe_while_talking, 0);
  EXPECT_GE(st.link.rejected(), 1);
  EXPECT_GT(st.safe_periods, 10);
  EXPECT_EQ(st.telemetry_records, static_cast<unsigned long long>(st.periods));
  EXPECT_EQ(st.telemetry_dropped, 0u);
  std::ifstream in(run.telemetry_csv);
  long lines = 0;
  for (std::string l; std::getline(in, l);) ++lines;
  EXPECT_EQ(lines, st.periods + 1);
}

}  // namespace
}  // namespace tmpc
