// The plant process: link loss holds the last input for plant_hold_s, then applies
// the plant's safe command (hover thrust, servo torques off), flagged and timed; a
// restarted controller is adopted at its second frame. And closed loops over a
// pseudo-terminal pair where the plant, then the controller, is killed and restarted
// in the middle of the mission: the pair reconnects within a few periods and the
// mission tracks again.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include <gtest/gtest.h>

#include "../sim/turned_tour.hpp"
#include "../synthesis/design_fixture.hpp"
#include "stall_monitor.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/runtime/controller_loop.hpp"
#include "tmpc/runtime/plant_loop.hpp"

namespace tmpc {
namespace {

/// The controller's side, scripted: after the plant's k-th state frame it answers with
/// control(k) (session, u), or stays silent when that returns session 0.
class ScriptedController : public io::Transport {
 public:
  using Script = std::function<io::ControlFrame(int)>;
  explicit ScriptedController(Script s) : script_(std::move(s)) {}
  long read_some(std::uint8_t* buf, std::size_t cap) override {
    if (pending_.empty()) return 0;
    const std::size_t n = std::min(cap, pending_.size());
    std::copy(pending_.begin(), pending_.begin() + static_cast<long>(n), buf);
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(n));
    return static_cast<long>(n);
  }
  bool write_all(const std::uint8_t*, std::size_t, int) override {
    const io::ControlFrame c = script_(++frames_);
    if (c.session != 0) io::encode(c, pending_);
    return true;
  }

 private:
  Script script_;
  std::vector<std::uint8_t> pending_;
  int frames_ = 0;
};

io::ControlFrame control(std::uint32_t session, std::uint32_t seq, const Eigen::Vector4d& u) {
  io::ControlFrame c;
  c.session = session;
  c.seq = seq;
  c.n = 4;
  for (int i = 0; i < 4; ++i) c.u[static_cast<std::size_t>(i)] = u(i);
  return c;
}

TEST(PlantLoop, LinkLossHoldsTheLastInputThenAppliesTheHoverSafeCommand) {
  const Config cfg = test::quick_config();
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle), cfg.envelope.yaw);
  const Eigen::Vector4d u_hold(eq.u(0) + 0.1, eq.u(1) - 0.1, 0.01, -0.01);
  // Controls for the first 20 periods, then nothing.
  ScriptedController link([&](int k) { return k <= 20 ? control(5, static_cast<std::uint32_t>(k), u_hold) : io::ControlFrame{}; });
  PlantLoopOptions o;
  o.duration_s = 40 * cfg.sample_time;
  std::atomic<bool> stop{false};
  const PlantLoopStats st = run_plant_loop(PlantSetup::from_config(cfg), test::quiet_helix(), link, o, stop);
  EXPECT_EQ(st.periods, 40);
  EXPECT_EQ(st.controls, 20);
  // plant_hold_s = 0.1 s: 8 periods (96 ms) hold the last input, the 9th is past it.
  EXPECT_DOUBLE_EQ(cfg.link.plant_hold_s, 0.1);
  EXPECT_EQ(st.held_periods, 8);
  EXPECT_EQ(st.safe_command_periods, 12);
  EXPECT_EQ(st.link_losses, 1);
  EXPECT_NEAR(st.first_link_loss_s, 28 * cfg.sample_time, 1e-9);
  EXPECT_DOUBLE_EQ(st.last_input[0], eq.u(0));
  EXPECT_DOUBLE_EQ(st.last_input[1], eq.u(1));
  EXPECT_EQ(st.last_input[2], 0.0);
  EXPECT_EQ(st.last_input[3], 0.0);
}

TEST(PlantLoop, ARestartedControllerIsAdoptedAtItsSecondFrame) {
  const Config cfg = test::quick_config();
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle), cfg.envelope.yaw);
  const Eigen::Vector4d u1(eq.u(0), eq.u(1), 0.0, 0.0), u2(eq.u(0) + 0.2, eq.u(1) + 0.2, 0.0, 0.0);
  // Controller 1 (session 11) for 10 periods, controller 2 (session 22, counting from 1) after.
  ScriptedController link([&](int k) {
    return k <= 10 ? control(11, static_cast<std::uint32_t>(k), u1) : control(22, static_cast<std::uint32_t>(k - 10), u2);
  });
  PlantLoopOptions o;
  o.duration_s = 20 * cfg.sample_time;
  std::atomic<bool> stop{false};
  const PlantLoopStats st = run_plant_loop(PlantSetup::from_config(cfg), test::quiet_helix(), link, o, stop);
  EXPECT_EQ(st.controller_sessions, 2);
  EXPECT_EQ(st.controls, 19);  // all but the new session's first frame
  EXPECT_EQ(st.link[io::Reject::Session], 1);
  EXPECT_EQ(st.peer_session, 22u);
  EXPECT_DOUBLE_EQ(st.last_input[0], u2(0));
  EXPECT_EQ(st.safe_command_periods, 0);
}

// The plant's true errors are the controller's: for an any-yaw design, x and y along
// and across the mission reference's heading. Oracle: the physics' symmetry. A tour
// turned by 1 rad about the vertical, flown on the same body-frame inputs (hover, so
// that the vehicle stays behind the reference as it sets off), has the same errors in
// that frame; in the world frame its lag would split between x and y.
TEST(PlantLoop, AnAnyYawPlantTakesItsErrorsInTheReferencesYawFrame) {
  const Config cfg = test::quick_config();
  ASSERT_TRUE(cfg.envelope.any_yaw());
  const PlantSetup setup = PlantSetup::from_config(cfg);
  ASSERT_TRUE(setup.yaw_frame.has_value());
  EXPECT_EQ(*setup.yaw_frame, cfg.envelope.yaw);
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle), cfg.envelope.yaw);
  const Eigen::Vector4d u_hover = eq.u;
  auto fly = [&](double a) {
    ScriptedController link([&](int k) { return control(7, static_cast<std::uint32_t>(k), u_hover); });
    PlantLoopOptions o;
    o.duration_s = 150 * cfg.sample_time;
    std::atomic<bool> stop{false};
    return run_plant_loop(setup, test::turned_tour(a), link, o, stop);
  };
  const PlantLoopStats s0 = fly(0.0), s1 = fly(1.0);
  ASSERT_FALSE(s0.diverged);
  ASSERT_FALSE(s1.diverged);
  ASSERT_EQ(s0.periods, 150);
  ASSERT_EQ(s1.periods, 150);
  // Both horizontal errors are there to be mixed by a turn (the vehicle lags behind).
  EXPECT_GT(s0.rmse[0], 1e-3);
  EXPECT_GT(s0.rmse[1], 1e-3);
  for (std::size_t i = 0; i < s0.rmse.size(); ++i) EXPECT_NEAR(s1.rmse[i], s0.rmse[i], 1e-9 + 1e-6 * s0.rmse[i]) << i;
  EXPECT_NEAR(s1.max_position_error, s0.max_position_error, 1e-9);
  // In the world frame (no yaw frame) the turned flight's x error is another.
  PlantSetup world = setup;
  world.yaw_frame.reset();
  ScriptedController link([&](int k) { return control(7, static_cast<std::uint32_t>(k), u_hover); });
  PlantLoopOptions o;
  o.duration_s = 150 * cfg.sample_time;
  std::atomic<bool> stop{false};
  const PlantLoopStats w1 = run_plant_loop(world, test::turned_tour(1.0), link, o, stop);
  EXPECT_GT(std::abs(w1.rmse[0] - s0.rmse[0]), 0.05 * s0.rmse[0]);  // 9 % off
}

const ControllerArtifact& artifact() {
  static const ControllerArtifact a = test::quick_artifact();
  return a;
}

/// A hardware-in-the-loop run over a pseudo-terminal pair in which one side is killed
/// after `first_s` and a new process of it starts at once (a new session).
struct RestartRun {
  PlantLoopStats plant_a, plant_b;
  ControllerLoopStats ctrl_a, ctrl_b;
  double host_stall_ms = 0.0;
};

RestartRun restart_run(bool restart_plant, double first_s, double second_s) {
  const PlantSetup setup = PlantSetup::from_config(test::quick_config());
  const Scenario scenario = test::quiet_helix();
  artifact();  // the design happens once, before either side starts
  io::PtyPair pty = io::open_pty_pair();
  auto port = io::open_serial(pty.slave_path);
  RestartRun r;
  test::StallMonitor monitor;
  PlantLoopOptions po;
  po.time_scale = test::kWallTimeScale;
  std::atomic<bool> stop_plant{false}, stop_ctrl{false};
  if (restart_plant) {
    ControllerLoopOptions co;
    co.trajectory = scenario.trajectory;
    co.time_scale = test::kWallTimeScale;
    std::thread ctrl([&] { r.ctrl_a = run_controller_loop(artifact(), *port, co, stop_ctrl); });
    po.duration_s = first_s;
    r.plant_a = run_plant_loop(setup, scenario, *pty.master, po, stop_plant);
    // Killed mid-frame: half a state frame of the dead process is left on the line.
    const std::uint8_t partial[] = {0x05, 0x02, 0x01, 0x9a, 0x33};
    pty.master->write_all(partial, sizeof partial);
    po.duration_s = second_s;
    r.plant_b = run_plant_loop(setup, scenario, *pty.master, po, stop_plant);
    stop_ctrl.store(true);
    ctrl.join();
  } else {
    po.duration_s = first_s + second_s;
    std::atomic<bool> plant_done{false};
    std::thread plant([&] {
      r.plant_a = run_plant_loop(setup, scenario, *pty.master, po, stop_plant);
      plant_done.store(true);
      stop_ctrl.store(true);
    });
    ControllerLoopOptions co;
    co.trajectory = scenario.trajectory;
    co.time_scale = test::kWallTimeScale;
    co.duration_s = first_s;
    r.ctrl_a = run_controller_loop(artifact(), *port, co, stop_ctrl);
    co.duration_s = 0.0;  // a new process (a new session), until the plant's mission ends
    if (!plant_done.load()) r.ctrl_b = run_controller_loop(artifact(), *port, co, stop_ctrl);
    plant.join();
  }
  r.host_stall_ms = monitor.stop();
  return r;
}

TEST(PlantLoop, AKilledAndRestartedPlantReconnectsAndTheMissionTracksAgain) {
  RestartRun r;
  for (int attempt = 1; attempt <= 3; ++attempt) {
    r = restart_run(true, 2.0, 3.0);
    // The controller adopted the new plant's session and restarted its law from it.
    EXPECT_EQ(r.ctrl_a.link.session_changes, 1);
    EXPECT_GE(r.ctrl_a.restarts, 2);
    EXPECT_EQ(r.ctrl_a.peer_session, r.plant_b.session);
    EXPECT_FALSE(r.plant_b.diverged);
    if (r.host_stall_ms < 6.0 * test::kWallTimeScale) break;
    std::printf("attempt %d: host stall of %.1f ms; again\n", attempt, r.host_stall_ms);
  }
  if (r.host_stall_ms >= 6.0 * test::kWallTimeScale) GTEST_SKIP() << "the host stalled threads by " << r.host_stall_ms << " ms in three runs";
  // The new plant got the law within a few periods and tracks the mission from its start
  // (one more period per deadline the controller missed or period it woke late).
  const long late = r.ctrl_a.late + r.ctrl_a.busy + r.ctrl_a.skipped + r.ctrl_a.late_wakes;
  EXPECT_LE(r.plant_b.periods_without_control, 2 + late)
      << "new plant: controls " << io::summary(r.plant_b.link) << ", longest silence " << r.plant_b.longest_silence_periods
      << " periods; controller: states " << io::summary(r.ctrl_a.link) << ", " << r.ctrl_a.states << " periods with a state, "
      << r.ctrl_a.restarts << " law restarts, " << r.ctrl_a.safe_periods << " safe, " << r.ctrl_a.late << " late, "
      << r.ctrl_a.busy << " busy, " << r.ctrl_a.skipped << " skipped, " << r.ctrl_a.late_wakes << " woken late";
  EXPECT_EQ(r.plant_b.safe_command_periods, 0);
  EXPECT_LT(r.plant_b.max_position_error, 0.01);
  EXPECT_LT(r.plant_b.max_position_error_final_s, 0.01);
  std::printf("plant restart: the new plant went %ld periods without a control, max position error %.2e m\n",
              r.plant_b.periods_without_control, r.plant_b.max_position_error);
}

TEST(PlantLoop, AKilledAndRestartedControllerIsAdoptedAndTheMissionTracksOn) {
  RestartRun r;
  for (int attempt = 1; attempt <= 3; ++attempt) {
    r = restart_run(false, 2.0, 3.0);
    EXPECT_EQ(r.plant_a.controller_sessions, 2);
    EXPECT_NE(r.ctrl_a.session, r.ctrl_b.session);
    EXPECT_FALSE(r.plant_a.diverged);
    if (r.host_stall_ms < 6.0 * test::kWallTimeScale) break;
    std::printf("attempt %d: host stall of %.1f ms; again\n", attempt, r.host_stall_ms);
  }
  if (r.host_stall_ms >= 6.0 * test::kWallTimeScale) GTEST_SKIP() << "the host stalled threads by " << r.host_stall_ms << " ms in three runs";
  // Between the two processes the plant held the last input, then hovered (its safe
  // command) for as long as the new controller took to start; once its session was
  // adopted (its second frame) every period had a control, and the mission tracks.
  // A period whose solve missed the deadline sends the fallback at the deadline, 0.8 T
  // after the loop woke: with the two free-running clocks' phases more than 0.7 T apart
  // that is past the plant's wait (1.5 T), one silent period each (the new process's
  // first solves run cold, beside another test on a 2-core host); so does a period the
  // host woke the loop more than half a period late (the StallMonitor's thread, on the
  // other core, may not see it).
  const long late = r.ctrl_b.late + r.ctrl_b.busy + r.ctrl_b.skipped + r.ctrl_b.late_wakes;
  EXPECT_LE(r.plant_a.silent_periods_last_session, 2 + late)
      << "new controller: states " << io::summary(r.ctrl_b.link) << ", " << r.ctrl_b.states << " periods with a state, "
      << r.ctrl_b.late << " late, " << r.ctrl_b.busy << " busy, " << r.ctrl_b.skipped << " skipped, "
      << r.ctrl_b.late_wakes << " woken late, wake latency max "
      << r.ctrl_b.wake_latency_max_us << " us, solve max " << r.ctrl_b.solve_max_us << " us; host stall "
      << r.host_stall_ms << " ms";
  EXPECT_LT(r.plant_a.max_position_error_final_s, 0.01);
  EXPECT_LT(r.plant_a.max_position_error, 0.1);
  std::printf("controller restart: longest silence %ld periods (%ld on the plant's safe command), %ld after the new "
              "session; max position error %.2e m, %.2e m in the final second\n",
              r.plant_a.longest_silence_periods, r.plant_a.safe_command_periods, r.plant_a.silent_periods_last_session,
              r.plant_a.max_position_error, r.plant_a.max_position_error_final_s);
}

}  // namespace
}  // namespace tmpc
