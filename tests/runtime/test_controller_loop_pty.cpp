// The on-board loop over a pseudo-terminal on the wall clock, the test playing the
// plant: what only a real transport and real threads show. Valid states get the tube
// law; a silent link triggers the safe command, flagged in every control frame until
// states return; garbage on the line is counted, never fatal; every period leaves a
// telemetry record. The timing-independent checks hold in every run. The timing checks
// hold unless an independent sleeper thread saw the host stall (stall_monitor.hpp):
// such a run is repeated (up to three times), as is a run whose loop woke late; a loop
// late in every run on a quiet host fails.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "scripted_plant.hpp"
#include "stall_monitor.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/controller_loop.hpp"

namespace tmpc {
namespace {

/// One run: once the loop answers, the plant side sends 30 periods of states, is silent
/// for 25, sends 30 more; the control frames it gets back, counted by their flags.
struct SilentLinkRun {
  ControllerLoopStats st;
  int got = 0, safe_while_talking = 0, safe_while_silent = 0, normal_while_silent = 0;
  double host_stall_ms = 0.0;
  std::string telemetry_csv;
};

SilentLinkRun silent_link_run(const ControllerArtifact& a, ReferenceGenerator& traj) {
  SilentLinkRun run;
  io::PtyPair pty = io::open_pty_pair();
  auto port = io::open_serial(pty.slave_path);
  ControllerLoopOptions o;
  o.trajectory = traj.shared_trajectory();
  o.silent_periods = 5;
  o.telemetry_csv = run.telemetry_csv = ::testing::TempDir() + "loop_telemetry.csv";
  std::atomic<bool> stop{false};
  test::StallMonitor monitor;
  std::thread loop([&] { run.st = run_controller_loop(a, *port, o, stop); });

  io::Decoder controls(io::control_decoder_settings(4));
  std::uint8_t buf[512];
  // Like a plant, start the script once the controller answers: its set-up (solver
  // factorisation, telemetry file) takes a variable time (long under a sanitizer), and
  // a frame count over a window the loop was not yet running in would judge the host.
  // Before any state the loop sends the safe command every period.
  const auto up_by = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  bool answered = false;
  while (!answered && std::chrono::steady_clock::now() < up_by) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    for (long n; !answered && (n = pty.master->read_some(buf, sizeof(buf))) > 0;) {
      for (long i = 0; i < n; ++i) answered = controls.push(buf[i]) || answered;
    }
  }
  EXPECT_TRUE(answered) << "the controller loop sent no frame within 20 s of its start";
  const auto period = std::chrono::milliseconds(12);
  auto next = std::chrono::steady_clock::now();
  for (int k = 0; k < 85; ++k) {
    const bool silent = k >= 30 && k < 55;
    if (!silent) {
      const double t = 0.012 * k;
      const std::vector<std::uint8_t> bytes = test::state_bytes(77, static_cast<std::uint32_t>(k + 1), t, traj.at(t));
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
  run.host_stall_ms = monitor.stop();
  return run;
}

TEST(ControllerLoopPty, SilentLinkTriggersTheSafeCommandUntilStatesReturn) {
  const ControllerArtifact a = test::quick_artifact();
  const Config cfg = test::quick_config();
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator traj(model, test::thesis_helix(), cfg.attitude);
  // The timing is judged on the quiet run (no host stall) whose loop woke the least late:
  // one late wake on a shared 2-core host can be another thread's time slice, a late loop
  // in every quiet run is the loop's fault.
  SilentLinkRun run;
  bool have_quiet = false;
  double worst_stall_ms = 0.0;
  for (int attempt = 1; attempt <= 3; ++attempt) {
    SilentLinkRun r = silent_link_run(a, traj);
    // What does not depend on timing, in every run.
    const ControllerLoopStats& st = r.st;
    EXPECT_GE(st.link[io::Reject::Framing] + st.link[io::Reject::Crc], 1);  // the garbage
    EXPECT_EQ(st.telemetry_records, static_cast<unsigned long long>(st.periods));
    EXPECT_EQ(st.telemetry_dropped, 0u);
    std::ifstream in(r.telemetry_csv);
    long lines = 0;
    for (std::string l; std::getline(in, l);) ++lines;
    EXPECT_EQ(lines, st.periods + 1);
    worst_stall_ms = std::max(worst_stall_ms, r.host_stall_ms);
    if (r.host_stall_ms >= 6.0) {
      std::printf("attempt %d: an independent sleeper woke %.1f ms late (host stall); the timing checks again\n",
                  attempt, r.host_stall_ms);
      continue;
    }
    if (!have_quiet || r.st.wake_latency_max_us < run.st.wake_latency_max_us) run = r;
    have_quiet = true;
    if (run.st.wake_latency_max_us < 6000.0) break;
    std::printf("attempt %d: the loop woke %.0f us late on a quiet host (sleeper %.1f ms); again\n", attempt,
                r.st.wake_latency_max_us, r.host_stall_ms);
  }
  if (!have_quiet) {
    GTEST_SKIP() << "the host stalled an independent thread by up to " << worst_stall_ms
                 << " ms in all three runs: the timing checks cannot be judged here (the others passed)";
  }
  // Timing: on a host that ran its threads, a loop late in every run is the loop's fault.
  const ControllerLoopStats& st = run.st;
  EXPECT_LT(st.wake_latency_max_us, 6000.0) << "the loop woke late in every quiet run";
  EXPECT_GT(run.got, 60);
  EXPECT_GT(run.safe_while_silent, 10);
  EXPECT_EQ(run.normal_while_silent, 0);
  EXPECT_EQ(run.safe_while_talking, 0);
  EXPECT_GT(st.safe_periods, 10);
}

}  // namespace
}  // namespace tmpc
