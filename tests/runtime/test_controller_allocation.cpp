// The controller loop allocates nothing once it runs: a global operator new that
// counts the allocations of the loop's own thread (the optimizer and telemetry
// writer threads have their own tests or may allocate once at start), switched on by
// a scripted plant transport (scripted_plant.hpp) after 10 periods and off after 100 more.
#include <atomic>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../allocation_counter.hpp"
#include "../synthesis/design_fixture.hpp"
#include "scripted_plant.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/controller_loop.hpp"

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

}  // namespace
}  // namespace tmpc
