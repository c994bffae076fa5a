// The on-board loop's logic on a virtual clock (deterministic on any machine): the
// deadline rule (late, busy, fallback exactly then), the watchdog's default and the
// safe command's content, the plausibility gates (a lone implausible frame is missing,
// a sustained jump is re-anchored), a restarted plant adopted as a new session, and a
// telemetry record every period. The plant side is scripted (scripted_plant.hpp), the
// optimizer is a real solver whose completion times are scripted on the same clock.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "scripted_plant.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/controller_loop.hpp"
#include "tmpc/runtime/estimator_choice.hpp"
#include "tmpc/runtime/tube_controller.hpp"

namespace tmpc {
namespace {

constexpr std::uint32_t kPlant = 0xa11ce;

const ControllerArtifact& artifact() {
  static const ControllerArtifact a = test::quick_artifact();
  return a;
}

ReferenceGenerator& helix() {
  static const Config cfg = test::quick_config();
  static const TiltrotorModel model(cfg.vehicle);
  static ReferenceGenerator traj(model, test::thesis_helix(), cfg.attitude);
  return traj;
}

/// A real solver whose k-th solve (1-based) finishes duration(k) ns after it started,
/// on the loop's virtual clock: busy until then, its result visible only then.
class ScriptedOptimizer final : public Optimizer {
 public:
  ScriptedOptimizer(const VirtualClock& clock, std::function<std::int64_t(int)> duration,
                    const ControllerArtifact& a = artifact())
      : clock_(clock), duration_(std::move(duration)), solver_(make_solver("admm", a.qp(tube_law_options(a).offset_free))) {}
  std::uint64_t start(const Eigen::VectorXd& x0) override {
    if (busy()) return 0;
    ++calls_;
    result_ = solver_->solve(x0);
    done_at_ = clock_.now_ns() + duration_(calls_);
    return ++ticket_;
  }
  const SolveResult* poll(std::uint64_t ticket) const override {
    return ticket == ticket_ && clock_.now_ns() >= done_at_ ? &result_ : nullptr;
  }
  void abandon(std::uint64_t) override { ++abandoned_; }
  bool busy() const override { return clock_.now_ns() < done_at_; }
  int calls() const { return calls_; }
  int abandoned() const { return abandoned_; }

 private:
  const VirtualClock& clock_;
  std::function<std::int64_t(int)> duration_;
  std::unique_ptr<QpSolver> solver_;
  SolveResult result_;
  std::int64_t done_at_ = 0;
  std::uint64_t ticket_ = 0;
  int calls_ = 0, abandoned_ = 0;
};

/// Frames of the plant flying the reference: period k (0-based) carries the state at
/// t = 0.012 k with sequence number k + 1; `edit` may change or drop (empty) a frame.
std::vector<std::vector<std::uint8_t>> reference_frames(
    int periods, const std::function<std::vector<std::uint8_t>(int, std::vector<std::uint8_t>)>& edit = {}) {
  std::vector<std::vector<std::uint8_t>> frames;
  for (int k = 0; k < periods; ++k) {
    const double t = 0.012 * k;
    std::vector<std::uint8_t> f = test::state_bytes(kPlant, static_cast<std::uint32_t>(k + 1), t, helix().at(t));
    frames.push_back(edit ? edit(k, f) : f);
  }
  return frames;
}

struct LoopRun {
  ControllerLoopStats st;
  std::unique_ptr<test::ScriptedPlant> plant;
  int solves = 0;
};

/// The loop over `frames` for `periods` periods on a virtual clock; solve k takes
/// duration(k) ns (default 1 ms).
LoopRun run_loop(std::vector<std::vector<std::uint8_t>> frames, int periods,
             std::function<std::int64_t(int)> duration = [](int) { return std::int64_t{1000000}; },
             ControllerLoopOptions o = {}) {
  LoopRun r;
  VirtualClock clock(artifact().sample_time);
  ScriptedOptimizer opt(clock, duration);
  std::atomic<bool> stop{false};
  r.plant = std::make_unique<test::ScriptedPlant>(std::move(frames), [&](int k) {
    if (k >= periods) stop.store(true);
  });
  o.session = 0xc0de;
  o.trajectory = test::thesis_helix();
  ControllerLoopSeams seams;
  seams.clock = &clock;
  seams.optimizer = &opt;
  r.st = run_controller_loop(artifact(), *r.plant, o, stop, seams);
  r.solves = opt.calls();
  return r;
}

/// The loop over a closed-loop link (the trajectory: the thesis helix) for `periods`
/// periods on a virtual clock, each solve taking 1 ms.
ControllerLoopStats run_closed_loop(io::Transport& link, int periods, ControllerLoopOptions o = {}) {
  VirtualClock clock(artifact().sample_time);
  ScriptedOptimizer opt(clock, [](int) { return std::int64_t{1000000}; });
  std::atomic<bool> stop{false};
  o.trajectory = test::thesis_helix();
  o.duration_s = periods * artifact().sample_time;
  ControllerLoopSeams seams;
  seams.clock = &clock;
  seams.optimizer = &opt;
  return run_controller_loop(artifact(), link, o, stop, seams);
}

/// Hover 2 m up, yaw 0.
std::shared_ptr<const Trajectory> hover_at_2m() { return make_hover({Eigen::Vector3d(0, 0, 2), 0.0}); }

/// The tiltrotor's Euler-Lagrange plant under `d`, started on `t`'s reference at t = 0.
std::unique_ptr<Plant> plant_on(const Config& cfg, const std::shared_ptr<const Trajectory>& t, DisturbanceProfile d) {
  auto plant = std::make_unique<ElPlant>(cfg.vehicle, std::move(d), cfg.simulation.substep);
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator gen(model, t, cfg.attitude);
  const ReferencePoint r0 = gen.at(0.0);
  Eigen::VectorXd x0(20);
  x0 << r0.q, r0.qd;
  plant->reset(x0, 0.0);
  return plant;
}

// `tmpc hil` starts its plant when the controller says it is ready (the law, the
// solver and the clock built): the flag is set before the first period reads the link,
// and before nothing else.
TEST(ControllerLoop, SaysItIsReadyBeforeItsFirstPeriod) {
  std::atomic<bool> ready{false};
  std::vector<bool> seen;  // the flag at each period's control
  VirtualClock clock(artifact().sample_time);
  ScriptedOptimizer opt(clock, [](int) { return std::int64_t{1000000}; });
  std::atomic<bool> stop{false};
  test::ScriptedPlant plant(reference_frames(5), [&](int k) {
    seen.push_back(ready.load());
    if (k >= 3) stop.store(true);
  });
  ControllerLoopOptions o;
  o.trajectory = test::thesis_helix();
  o.ready = &ready;
  ControllerLoopSeams seams;
  seams.clock = &clock;
  seams.optimizer = &opt;
  EXPECT_FALSE(ready.load());
  const ControllerLoopStats st = run_controller_loop(artifact(), plant, o, stop, seams);
  ASSERT_FALSE(seen.empty());
  for (bool r : seen) EXPECT_TRUE(r);
  EXPECT_GE(st.periods, 3);
}

TEST(ControllerLoop, FallbackExactlyWhenTheOptimizerIsLateOrBusy) {
  // Solve 2 takes 30 ms: late in period 2 (deadline 9.6 ms), still running at the
  // start of periods 3 and 4 (12 and 24 ms after it started), done before period 5.
  const LoopRun r = run_loop(reference_frames(10), 10, [](int k) { return std::int64_t{k == 2 ? 30000000 : 1000000}; });
  EXPECT_EQ(r.st.periods, 10);
  EXPECT_EQ(r.st.late, 1);
  EXPECT_EQ(r.st.busy, 2);
  EXPECT_EQ(r.st.fallback_periods, 3);
  EXPECT_EQ(r.st.optimizer_used, 7);
  EXPECT_EQ(r.solves, 8);
  EXPECT_EQ(r.st.skipped, 0);
  for (int k = 1; k <= 10; ++k) {
    const bool fallback = (r.plant->control(k).flags & io::ControlFrame::kFallback) != 0;
    EXPECT_EQ(fallback, k >= 2 && k <= 4) << "period " << k;
    EXPECT_EQ(r.plant->control(k).session, 0xc0deu);
    EXPECT_EQ(r.plant->control(k).seq, static_cast<std::uint32_t>(k));
  }
}

TEST(ControllerLoop, ASolveWithinTheDeadlineIsUsedAndOneJustPastItIsNot) {
  // The deadline is 80 % of the period: 9.6 ms after the boundary.
  const LoopRun in_time = run_loop(reference_frames(5), 5, [](int) { return std::int64_t{9500000}; });
  EXPECT_EQ(in_time.st.late, 0);
  EXPECT_EQ(in_time.st.fallback_periods, 0);
  const LoopRun late = run_loop(reference_frames(5), 5, [](int) { return std::int64_t{9700000}; });
  EXPECT_EQ(late.st.late, 5);
  EXPECT_EQ(late.st.fallback_periods, 5);
}

TEST(ControllerLoop, WatchdogDefaultsToTenPeriodsAndSendsTheLastFeedforwardWithZeroTorques) {
  // States for periods 1-30, silence for 31-55, states again from 56.
  const auto frames = reference_frames(85, [](int k, std::vector<std::uint8_t> f) {
    return k >= 30 && k < 55 ? std::vector<std::uint8_t>{} : f;
  });
  const LoopRun r = run_loop(frames, 85);
  EXPECT_EQ(r.st.watchdog_periods, 10);
  // Silent periods 31..40 still get the law from the last state; 41..55 the safe command.
  EXPECT_EQ(r.st.safe_periods, 15);
  const Config cfg = test::quick_config();
  const TiltrotorModel model(cfg.vehicle);
  const Eigen::Vector4d u_r = feedforward(model, helix().at(0.012 * 29));  // the last state's feedforward
  for (int k = 1; k <= 85; ++k) {
    const io::ControlFrame& c = r.plant->control(k);
    const bool safe = (c.flags & io::ControlFrame::kSafe) != 0;
    EXPECT_EQ(safe, k >= 41 && k <= 55) << "period " << k;
    if (safe) {
      EXPECT_NEAR(c.u[0], u_r(0), 1e-9) << "period " << k;  // the trims are warm-started differently
      EXPECT_NEAR(c.u[1], u_r(1), 1e-9);
      EXPECT_EQ(c.u[2], 0.0);
      EXPECT_EQ(c.u[3], 0.0);
    }
  }
  EXPECT_EQ(r.st.restarts, 1);  // the first state only: the link's return is the same track
  EXPECT_EQ(r.st.link.rejected_total(), 0);
}

TEST(ControllerLoop, BeforeAnyStateTheSafeCommandIsTheHoverInput) {
  const LoopRun r = run_loop(std::vector<std::vector<std::uint8_t>>(5), 5);
  for (int k = 1; k <= 5; ++k) {
    const io::ControlFrame& c = r.plant->control(k);
    EXPECT_TRUE(c.flags & io::ControlFrame::kSafe);
    EXPECT_DOUBLE_EQ(c.u[0], artifact().u_eq(0));
    EXPECT_DOUBLE_EQ(c.u[1], artifact().u_eq(1));
    EXPECT_EQ(c.u[2], 0.0);
    EXPECT_EQ(c.u[3], 0.0);
  }
  EXPECT_EQ(r.st.states, 0);
}

TEST(ControllerLoop, ALoneImplausibleFrameIsMissingAndASustainedJumpIsAdopted) {
  // A closed loop with the Euler-Lagrange plant: the frames are its state, except a
  // single frame 100 m off (period 20), one stamped 10 s in the past (period 30), and
  // from period 40 on an estimator that reads y 0.8 m off (a reset that stays).
  const Config cfg = test::quick_config();
  Eigen::VectorXd far = Eigen::VectorXd::Zero(20), moved = Eigen::VectorXd::Zero(20);
  far(0) = 100.0;
  moved(1) = 0.8;
  test::SimulatedPlantLink link(cfg, helix(), [&](int k, io::StateFrame f) {
    if (k == 20) return test::offset_bytes(f, far);
    if (k == 30) f.time -= 10.0;
    return test::offset_bytes(f, k >= 40 ? moved : Eigen::VectorXd::Zero(20));
  });
  const ControllerLoopStats st = run_closed_loop(link, 120);
  EXPECT_EQ(st.periods, 120);
  EXPECT_EQ(st.link[io::Reject::Jump], 1 + 2);  // the 100 m frame; two of the reset before it is adopted
  EXPECT_EQ(st.link[io::Reject::Time], 1);      // 10 s in the past
  EXPECT_EQ(st.link.resyncs, 1);
  EXPECT_EQ(st.restarts, 2);                    // first state, the adopted track
  EXPECT_EQ(st.safe_periods, 0);
  EXPECT_EQ(st.states, 120);                    // a rejected frame leaves the last state in use
  // The 100 m frame never reached the law: the plant stayed near the reference until
  // the reset, after which the law flies the (believed) error away.
  EXPECT_FALSE(link.plant().state().hasNaN());
}

TEST(ControllerLoop, ARestartedPlantIsANewSessionAndTheLawRestartsFromIt) {
  // Periods 0-39: the first plant process; from 40 a restarted one, counting its
  // sequence and its time from the start again (its mission restarted).
  const auto frames = reference_frames(80, [](int k, std::vector<std::uint8_t> f) {
    if (k < 40) return f;
    const double t = 0.012 * (k - 40);
    return test::state_bytes(0xbbbb, static_cast<std::uint32_t>(k - 39), t, helix().at(t));
  });
  ControllerLoopOptions o;
  o.telemetry_csv = ::testing::TempDir() + "loop_restart.csv";
  const LoopRun r = run_loop(frames, 80, [](int) { return std::int64_t{1000000}; }, o);
  EXPECT_EQ(r.st.link.session_changes, 1);
  EXPECT_EQ(r.st.link[io::Reject::Session], 1);  // the new session's first frame, before it is confirmed
  EXPECT_EQ(r.st.restarts, 2);
  EXPECT_EQ(r.st.peer_session, 0xbbbbu);
  EXPECT_EQ(r.st.safe_periods, 0);
  EXPECT_EQ(r.st.fallback_periods, 0);
  // Every period left a record; the restart and the new session are in it.
  EXPECT_EQ(r.st.telemetry_records, 80u);
  std::ifstream in(o.telemetry_csv);
  std::string header, line;
  std::getline(in, header);
  long lines = 0, restarts = 0;
  const auto columns = [](const std::string& l) {
    std::vector<std::string> c;
    std::size_t p = 0;
    for (std::size_t q; (q = l.find(',', p)) != std::string::npos; p = q + 1) c.push_back(l.substr(p, q - p));
    c.push_back(l.substr(p));
    return c;
  };
  const std::vector<std::string> names = columns(header);
  const auto at = [&](const char* n) { return std::find(names.begin(), names.end(), n) - names.begin(); };
  ASSERT_LT(at("restart"), static_cast<long>(names.size()));
  ASSERT_LT(at("rejected_session"), static_cast<long>(names.size()));
  std::string last;
  while (std::getline(in, line)) {
    ++lines;
    restarts += columns(line)[static_cast<std::size_t>(at("restart"))] == "1";
    last = line;
  }
  EXPECT_EQ(lines, 80);
  EXPECT_EQ(restarts, 2);
  EXPECT_EQ(columns(last)[static_cast<std::size_t>(at("rejected_session"))], "1");
}

// A closed loop whose state reads 0.5 m off the reference along x from its first frame
// (README "A start off the reference"; the Euler-Lagrange plant): the loop joins the
// reference from it at the law's start, so the hard QP stays feasible; straight to the
// reference the law flies the load fast enough that the hard QP turns infeasible (this
// test's optimizer is the plain ADMM, without the softened QP: the LQR fallback flies).
TEST(ControllerLoop, TheLawJoinsTheReferenceFromAStartOffIt) {
  const Config cfg = test::quick_config();
  const auto fly = [&](bool join) {
    Eigen::VectorXd off = Eigen::VectorXd::Zero(20);
    off(0) = 0.5;
    test::SimulatedPlantLink link(cfg, helix(), [&](int, io::StateFrame f) { return test::offset_bytes(f, off); });
    ControllerLoopOptions o;
    o.reference_join = join;
    return run_closed_loop(link, 300, o);
  };
  const ControllerLoopStats joined = fly(true), straight = fly(false);
  std::printf("0.5 m off: softened %ld, fallback %ld periods joined; %ld, %ld straight\n", joined.softened_periods,
              joined.fallback_periods, straight.softened_periods, straight.fallback_periods);
  EXPECT_EQ(joined.restarts, 1);
  EXPECT_EQ(joined.softened_periods, 0);
  EXPECT_EQ(joined.fallback_periods, 0);
  EXPECT_GT(straight.fallback_periods, 40);  // 83
}

TEST(ControllerLoop, ImplausibleValuesNeverReachTheController) {
  Eigen::VectorXd spin = Eigen::VectorXd::Zero(20);
  spin(13) = 99.0;  // 99 rad/s roll rate
  const auto frames = reference_frames(20, [&](int k, std::vector<std::uint8_t> f) {
    const double t = 0.012 * k;
    if (k == 5) return test::state_bytes(kPlant, 6, t, helix().at(t), spin);
    if (k == 8) return test::state_bytes(kPlant, 9, 1e8, helix().at(t));
    return f;
  });
  const LoopRun r = run_loop(frames, 20);
  EXPECT_EQ(r.st.link[io::Reject::Bounds], 2);
  EXPECT_EQ(r.st.link.accepted, 18);
  EXPECT_EQ(r.st.restarts, 1);
}

// The second system (two masses on springs: 4 measured states, 2 integrals, 2 inputs)
// through the same loop, frames and telemetry: the frames carry 4 values, the controls
// 2, the telemetry the artifact's names; the loop regulates a 0.2 m start offset and
// a 1 N step on the first mass (the offset-free law) back to the origin.
TEST(ControllerLoop, TheSecondSystemFliesThroughTheSameLoop) {
  const ControllerArtifact& a = test::mass_spring_artifact();
  ASSERT_EQ(a.n, 6);
  ASSERT_EQ(a.measured, 4);
  ASSERT_EQ(a.m, 2);
  DisturbanceEvent step;
  step.start = 2.0;
  step.force = Eigen::Vector3d(1.0, 0.0, 0.0);
  auto plant = make_linear_plant(a.linear_A, a.linear_B, a.linear_D, DisturbanceProfile({step}));
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(4);
  x0(0) = 0.2;
  plant->reset(x0, 0.0);
  test::SimulatedPlantLink link(std::move(plant), a.sample_time, {});
  VirtualClock clock(a.sample_time);
  ScriptedOptimizer opt(clock, [](int) { return std::int64_t{1000000}; }, a);
  std::atomic<bool> stop{false};
  ControllerLoopOptions o;
  o.trajectory = make_hover({Eigen::Vector3d::Zero(), 0.0});
  o.duration_s = 12.0;
  o.telemetry_csv = ::testing::TempDir() + "mass_spring_loop.csv";
  ControllerLoopSeams seams;
  seams.clock = &clock;
  seams.optimizer = &opt;
  const ControllerLoopStats st = run_controller_loop(a, link, o, stop, seams);
  EXPECT_EQ(st.periods, 600);
  EXPECT_EQ(st.states, 600);
  EXPECT_EQ(st.link.rejected_total(), 0);
  EXPECT_EQ(st.fallback_periods, 0);
  EXPECT_EQ(st.safe_periods, 0);
  // Regulated: both masses back near the origin 10 s after the step (the design's
  // slowest mode, the integrators', has a time constant of about 4.5 s; the step alone
  // would push the first mass 0.17 m off, the same offset more with the controller off).
  std::printf("mass-spring loop: state at 12 s %s\n", [&] {
    std::ostringstream os;
    os << link.plant().state().transpose();
    return os.str();
  }().c_str());
  EXPECT_LT(link.plant().state().head(2).cwiseAbs().maxCoeff(), 2e-3);
  std::ifstream in(o.telemetry_csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("period,t,e_p1,e_p2,e_v1,e_v2,e_int_p1,e_int_p2,r_p1,r_p2,r_v1,r_v2,", 0), 0u) << header;
  EXPECT_NE(header.find(",u_u1,u_u2,"), std::string::npos) << header;
  long rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_EQ(rows, 600);
}

TEST(ControllerLoop, YawingIntoTheForceTurnsTheVehicle) {
  // 1.2 N along x on the load from 0.5 s, hovering: the loop's governor turns the
  // reference's yaw until the force lies on the box's diagonal (-pi/4 or pi/4: the
  // nearer of the two from the mission's yaw 0), and the plant follows; without it the
  // yaw stays. The oracle is the plant's own yaw.
  const Config cfg = test::quick_config();
  const auto fly = [&](bool governed) {
    DisturbanceEvent step;
    step.start = 0.5;
    step.force = Eigen::Vector3d(1.2, 0.0, 0.0);
    const std::shared_ptr<const Trajectory> hover = hover_at_2m();
    auto plant = plant_on(cfg, hover, DisturbanceProfile({step}));
    test::SimulatedPlantLink link(std::move(plant), cfg.sample_time, {});
    VirtualClock clock(artifact().sample_time);
    ScriptedOptimizer opt(clock, [](int) { return std::int64_t{1000000}; });
    std::atomic<bool> stop{false};
    ControllerLoopOptions o;
    o.trajectory = hover;
    o.duration_s = 15.0;
    o.yaw_into_force = governed;
    ControllerLoopSeams seams;
    seams.clock = &clock;
    seams.optimizer = &opt;
    const ControllerLoopStats st = run_controller_loop(artifact(), link, o, stop, seams);
    EXPECT_EQ(st.safe_periods, 0);
    EXPECT_EQ(st.states, st.periods);
    return std::make_pair(link.plant().state()(5), st.fallback_periods);  // psi
  };
  const auto [held, held_fallbacks] = fly(false);
  const auto [turned, turned_fallbacks] = fly(true);
  std::printf("1.2 N on the load: yaw %.4f rad held, %.4f rad yawing into the force (fallback periods %ld, %ld)\n",
              held, turned, held_fallbacks, turned_fallbacks);
  EXPECT_LT(std::abs(held), 0.01);
  EXPECT_NEAR(std::abs(turned), M_PI / 4, 0.05);
  // The harness's optimizer solves the hard QP only (no softening): the step's first
  // periods fall back in both flights; the turn adds none.
  EXPECT_LE(turned_fallbacks, held_fallbacks);
}

// The estimator chosen for the loop (`tmpc controller` and `tmpc hil` take the same
// flags as `tmpc simulate`) is the one that flies. Oracle: the telemetry, column by
// column: `filtered` (the Kalman filter's estimate flew) and `step` (1: a disturbance
// step read with the lift kept, 2: with the lift re-opened). In hover with the design's
// sensor noise (5 mm, 0.3 degree, 0.031 m/s, 0.033 rad/s), the right rotor loses 15 %
// of its thrust at 3 s: a step of lift.
TEST(ControllerLoop, FliesTheEstimatorItIsGiven) {
  const Config cfg = test::quick_config();
  struct Flown {
    ControllerLoopStats st;
    long filtered = 0, rows = 0;
    int step_max = 0;
  };
  const auto fly = [&](const EstimatorChoice& e, const std::string& name) {
    const std::shared_ptr<const Trajectory> hover = hover_at_2m();
    auto plant = plant_on(cfg, hover, DisturbanceProfile{});
    std::mt19937_64 rng(5);
    std::normal_distribution<double> normal;
    test::SimulatedPlantLink link(std::move(plant), cfg.sample_time, [&](int, io::StateFrame f) {
      // q: x, y, z, 7 angles; qd: 3 velocities, 7 rates.
      for (std::size_t i = 0; i < 20; ++i) f.x[i] += (i < 3 ? 0.005 : i < 10 ? 0.00524 : i < 13 ? 0.031 : 0.033) * normal(rng);
      std::vector<std::uint8_t> bytes;
      io::encode(f, bytes);
      return bytes;
    });
    const int fault = static_cast<int>(3.0 / cfg.sample_time);
    link.set_actuator_edit([&](int k, Eigen::VectorXd& u) {
      if (k >= fault) u(0) *= 0.85;
    });
    VirtualClock clock(artifact().sample_time);
    ScriptedOptimizer opt(clock, [](int) { return std::int64_t{1000000}; });
    std::atomic<bool> stop{false};
    ControllerLoopOptions o;
    o.trajectory = hover;
    o.duration_s = 4.5;
    o.estimator = e;
    o.telemetry_csv = ::testing::TempDir() + "estimator_" + name + ".csv";
    ControllerLoopSeams seams;
    seams.clock = &clock;
    seams.optimizer = &opt;
    Flown f;
    f.st = run_controller_loop(artifact(), link, o, stop, seams);
    std::ifstream in(o.telemetry_csv);
    std::string header;
    std::getline(in, header);
    std::vector<std::string> names;
    {
      std::stringstream hs(header);
      for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
    }
    const auto col = [&](const std::string& c) {
      const auto it = std::find(names.begin(), names.end(), c);
      EXPECT_NE(it, names.end()) << c;
      return static_cast<std::size_t>(it - names.begin());
    };
    const std::size_t c_filtered = col("filtered"), c_step = col("step");
    for (std::string line; std::getline(in, line);) {
      std::vector<std::string> v;
      std::stringstream ls(line);
      for (std::string c; std::getline(ls, c, ',');) v.push_back(c);
      if (v.size() != names.size()) continue;
      ++f.rows;
      f.filtered += std::stol(v[c_filtered]);
      f.step_max = std::max(f.step_max, std::stoi(v[c_step]));
    }
    EXPECT_EQ(f.st.safe_periods, 0) << name;
    return f;
  };
  EstimatorChoice residual;
  residual.observer = "residual";
  EstimatorChoice kalman;
  kalman.observer = "kalman";
  EstimatorChoice keep = kalman;
  keep.step_reopens_lift = false;
  EstimatorChoice steady = kalman;
  steady.no_step_detection = true;
  const Flown r = fly(residual, "residual"), k = fly(kalman, "kalman"), kl = fly(keep, "keep"), s = fly(steady, "steady");
  std::printf("loop estimators: residual %s (%ld filtered of %ld), kalman %s (%ld of %ld; step %d), lift kept: step %d, "
              "no step detection: step %d\n",
              r.st.observer.c_str(), r.filtered, r.rows, k.st.observer.c_str(), k.filtered, k.rows, k.step_max, kl.step_max,
              s.step_max);
  EXPECT_EQ(r.st.observer, "residual");
  EXPECT_EQ(r.rows, 375);
  EXPECT_EQ(r.filtered, 0);
  EXPECT_EQ(k.st.observer, "kalman");
  EXPECT_EQ(k.filtered, k.rows);
  EXPECT_EQ(k.step_max, 2);   // read, and the lift re-opened
  EXPECT_EQ(kl.step_max, 1);  // read, the lift kept
  EXPECT_EQ(s.step_max, 0);   // not looked for
  // Mayne's law has no observer; a step option without the step detection is refused.
  EXPECT_EQ(flight_law_options(artifact(), "mayne", {}).offset_free, false);
  for (int option = 0; option < 3; ++option) {
    EstimatorChoice both;
    both.no_step_detection = true;
    (option == 0 ? both.step_reopens_lift : option == 1 ? both.step_corrects_input : both.late_step_keeps_gain) = false;
    try {
      flight_law_options(artifact(), "", both);
      ADD_FAILURE() << "step option " << option << " accepted without the step detection";
    } catch (const std::invalid_argument& ex) {
      EXPECT_NE(std::string(ex.what()).find("step detection"), std::string::npos) << ex.what();
    }
  }
  EstimatorChoice unknown;
  unknown.observer = "luenberger";
  EXPECT_THROW(flight_law_options(artifact(), "", unknown), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
