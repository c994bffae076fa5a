// The controller loop allocates nothing once it runs: a global operator new that
// counts the allocations of the loop's own thread (the optimizer and telemetry
// writer threads have their own tests or may allocate once at start), switched on by
// a scripted plant transport (scripted_plant.hpp) after 10 periods and off after 100 more.
#include <atomic>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../allocation_counter.hpp"
#include "../synthesis/design_fixture.hpp"
#include "scripted_plant.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/controller_loop.hpp"
#include "tmpc/runtime/controller_solver.hpp"
#include "tmpc/runtime/tube_controller.hpp"

namespace tmpc {
namespace {

using test::g_allocations;
using test::t_counting;

void expect_no_allocation(const std::string& law) {
  g_allocations = 0;
  const ControllerArtifact a = test::quick_artifact();
  const Config cfg = test::quick_config();
  const TiltrotorModel model(cfg.vehicle);
  ReferenceGenerator traj(model, test::thesis_helix(), cfg.attitude);
  std::vector<std::vector<std::uint8_t>> frames;
  for (int k = 0; k < 130; ++k) {
    const double t = 0.012 * k;
    const ReferencePoint r = traj.at(t);
    Eigen::VectorXd off = Eigen::VectorXd::Zero(20);
    for (int i = 0; i < 3; ++i) off(i) = 0.02 * std::sin(0.1 * k + i);  // off the reference
    frames.push_back(test::state_bytes(9, static_cast<std::uint32_t>(k + 1), t, r, off));
  }
  std::atomic<bool> stop{false};
  // Counting on from the 10th period, off (and the loop stopped) at the 110th.
  test::ScriptedPlant plant(frames, [&stop](int period) {
    if (period == 10) t_counting = true;
    if (period == 110) {
      t_counting = false;
      stop.store(true);
    }
  });
  ControllerLoopOptions o;
  o.trajectory = test::thesis_helix();
  o.tube_law = law;
  o.telemetry_csv = ::testing::TempDir() + "allocation_telemetry.csv";
  const ControllerLoopStats st = run_controller_loop(a, plant, o, stop);
  EXPECT_EQ(plant.controls(), 110);
  EXPECT_GE(st.states, 100);
  EXPECT_EQ(g_allocations.load(), 0) << "the controller loop allocated in 100 periods";
  std::printf("%s law, 100 counted periods: %ld allocations on the loop thread; %ld states, %ld optimizer results, %ld fallbacks\n",
              law.c_str(), g_allocations.load(), st.states, st.optimizer_used, st.fallback_periods);
}

TEST(ControllerLoopAllocation, NoAllocationPerPeriodMayneLaw) { expect_no_allocation("mayne"); }
TEST(ControllerLoopAllocation, NoAllocationPerPeriodOffsetFreeLaw) { expect_no_allocation("offset-free"); }

// The switched observer (both observers, the noise monitor, the blend) allocates nothing
// per period either: 300 periods of the tube law on the exact linear model, through the
// hand-over to the residual observer (period 84) and back to the filter when noise
// appears (period 200).
TEST(ControllerLoopAllocation, NoAllocationPerPeriodSwitchedObserver) {
  if (!test::kCountsAllocations) GTEST_SKIP() << "allocations are not counted under the sanitizer";
  const ControllerArtifact& a = test::quick_artifact();
  TubeController ctrl(a, make_solver("admm", a.qp(true)), tube_law_options(a));
  Eigen::VectorXd x = Eigen::VectorXd::Zero(a.n), meas(a.n), noise(a.n), u_n(a.m);
  const Eigen::VectorXd u_r = a.u_eq;
  for (int i = 0; i < a.n; ++i) noise(i) = i < a.measured ? 0.01 * std::sin(1.7 * i) : 0.0;
  ctrl.reset(x);
  bool was_residual = false, back_on_filter = false;
  g_allocations = 0;
  Eigen::VectorXd y(a.n);
  for (int k = 0; k < 300; ++k) {
    meas = x;
    if (k >= 200) meas += (k % 2 == 0 ? 1.0 : -1.0) * noise;  // a square-wave "noise" the monitor reads
    y = meas.cwiseQuotient(a.N_x);
    t_counting = k >= 10;
    const ControlStep& s = ctrl.step(y, u_r);
    t_counting = false;
    u_n = (s.u - a.u_eq).cwiseProduct(a.N_u);
    x = a.A * x + a.B * u_n;  // the plant (not counted)
    was_residual = was_residual || !s.filtered;
    back_on_filter = was_residual && s.filtered;
  }
  t_counting = false;
  EXPECT_TRUE(was_residual);
  EXPECT_TRUE(back_on_filter);
  EXPECT_EQ(g_allocations.load(), 0) << "the switched observer allocated in 290 periods";
}

// A step read and classified (tube_controller.hpp, step detection with the lift's
// GLR, step_signature.hpp) allocates nothing either: the filter alone on the exact
// linear model with the design's white noise, the right rotor at 85 % from period 300.
TEST(ControllerLoopAllocation, NoAllocationPerPeriodAtAClassifiedStep) {
  if (!test::kCountsAllocations) GTEST_SKIP() << "allocations are not counted under the sanitizer";
  const ControllerArtifact& a = test::quick_artifact();
  TubeControllerOptions o = tube_law_options(a, "offset-free", 0.0, "kalman");
  o.step_reopens_lift = true;
  TubeController ctrl(a, make_solver("active-set", a.qp(true)), o);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(a.n), meas(a.n), u(a.m), y(a.n);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  ctrl.reset(x);
  int steps = 0;
  g_allocations = 0;
  for (int k = 0; k < 500; ++k) {
    meas = x;
    for (std::size_t j = 0; j < a.estimator_rows.size(); ++j) {  // the design's noise (normalized)
      meas(a.estimator_rows[j]) += a.estimator_noise(static_cast<Eigen::Index>(j)) * normal(rng);
    }
    y = meas.cwiseQuotient(a.N_x);
    t_counting = k >= 10;
    const ControlStep& s = ctrl.step(y, a.u_eq);
    t_counting = false;
    steps += s.step_detected;
    u = s.u;
    if (k >= 300) u(0) *= 0.85;
    x = a.A * x + a.B * (u - a.u_eq).cwiseProduct(a.N_u);
  }
  EXPECT_GE(steps, 1) << "no step read";
  EXPECT_EQ(g_allocations.load(), 0) << "the filter allocated in 490 periods with a step read";
}

}  // namespace
}  // namespace tmpc
