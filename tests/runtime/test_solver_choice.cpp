// `--solver auto` (runtime/solver_choice.hpp): the decision rule on injected timings,
// and the calibration on this machine (no GPU here: the GPU candidate says why).
#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/runtime/solver_choice.hpp"

namespace tmpc {
namespace {

SolverTiming timing(const std::string& name, double p99, bool available = true, const std::string& reason = "") {
  SolverTiming t;
  t.name = name;
  t.available = available;
  t.reason = reason;
  t.samples = 100;
  t.p50_us = 0.5 * p99;
  t.p99_us = p99;
  t.max_us = 2.0 * p99;
  return t;
}

TEST(SolverChoice, TheGpuFliesWhenItFitsTheBudgetAtLeastAsWellAsTheCpu) {
  const SolverTiming cpu = timing("admm", 40.0);
  // Fits, faster or equal: the GPU.
  for (double g : {20.0, 40.0}) {
    const SolverTiming gpu = timing("admm-cuda", g);
    const SolverChoice c = choose_solver(cpu, &gpu, 9600.0);
    EXPECT_EQ(c.name, "admm-cuda") << g;
    EXPECT_NE(c.why.find("at least as well"), std::string::npos) << c.why;
    ASSERT_EQ(c.timings.size(), 2u);
  }
  // Fits, but slower than a CPU that fits: the CPU.
  const SolverTiming slow = timing("admm-cuda", 80.0);
  SolverChoice c = choose_solver(cpu, &slow, 9600.0);
  EXPECT_EQ(c.name, "admm");
  EXPECT_NE(c.why.find("CPU fits the budget better"), std::string::npos) << c.why;
  // The CPU misses the budget, the GPU fits: the GPU even if the CPU's p99 were smaller.
  const SolverTiming cpu_late = timing("admm", 12000.0), gpu_ok = timing("admm-cuda", 5000.0);
  EXPECT_EQ(choose_solver(cpu_late, &gpu_ok, 9600.0).name, "admm-cuda");
  // Only the CPU fits.
  const SolverTiming gpu_late = timing("admm-cuda", 10000.0);
  c = choose_solver(cpu, &gpu_late, 9600.0);
  EXPECT_EQ(c.name, "admm");
  EXPECT_NE(c.why.find("only the CPU fits"), std::string::npos) << c.why;
  // Neither fits: the faster, said so.
  const SolverTiming gpu_later = timing("admm-cuda", 11000.0);
  c = choose_solver(cpu_late, &gpu_later, 9600.0);
  EXPECT_EQ(c.name, "admm-cuda");
  EXPECT_NE(c.why.find("neither fits"), std::string::npos) << c.why;
}

TEST(SolverChoice, WithoutADeviceOrAGpuBuildTheCpuFliesAndTheReasonIsGiven) {
  const SolverTiming cpu = timing("admm", 40.0);
  SolverChoice c = choose_solver(cpu, nullptr, 9600.0);
  EXPECT_EQ(c.name, "admm");
  EXPECT_NE(c.why.find("no GPU solver in this build"), std::string::npos) << c.why;
  const SolverTiming none = timing("admm-cuda", 1.0, false, "no CUDA device");
  c = choose_solver(cpu, &none, 9600.0);
  EXPECT_EQ(c.name, "admm");  // even though its (stale) p99 would be smaller
  EXPECT_NE(c.why.find("admm-cuda unavailable (no CUDA device)"), std::string::npos) << c.why;
}

TEST(SolverChoice, TheCalibrationTimesTheArtifactsQpAndSaysWhyAGpuIsMissing) {
  const ControllerArtifact& a = test::quick_artifact();
  const SolverTiming cpu = time_solver("admm", a, true, 50);
  ASSERT_TRUE(cpu.available) << cpu.reason;
  EXPECT_EQ(cpu.samples, 50);
  EXPECT_GT(cpu.p50_us, 0.0);
  EXPECT_LE(cpu.p50_us, cpu.p99_us);
  EXPECT_LE(cpu.p99_us, cpu.max_us);
  // A solver that cannot be built for this form is unavailable with its reason, not an exception.
  const SolverTiming thesis = time_solver("explicit", a, true, 10);  // a partition over the nominal state only
  EXPECT_FALSE(thesis.available);
  EXPECT_FALSE(thesis.reason.empty());
  const SolverChoice c = auto_solver(a, true, 0.8, 30);
  const std::string gpu = gpu_solver_name();
  if (gpu.empty()) {
    EXPECT_EQ(c.name, cpu_solver_name());
    EXPECT_EQ(c.timings.size(), 1u);
  } else {
    ASSERT_EQ(c.timings.size(), 2u);
    if (!c.timings[1].available) {
      EXPECT_EQ(c.name, cpu_solver_name());  // no device here: the CPU, and why
      EXPECT_NE(c.why.find(c.timings[1].reason), std::string::npos);
      std::printf("no GPU: %s\n", c.why.c_str());
    }
  }
  std::printf("auto: %s (%s)\n", c.name.c_str(), c.why.c_str());
}

}  // namespace
}  // namespace tmpc
