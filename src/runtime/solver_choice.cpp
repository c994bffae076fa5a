// `--solver auto` (see solver_choice.hpp).
#include "tmpc/runtime/solver_choice.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "tmpc/runtime/controller_solver.hpp"
#include "tmpc/runtime/percentiles.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {

namespace {

std::string us(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f us", v);
  return b;
}

}  // namespace

SolverChoice choose_solver(const SolverTiming& cpu, const SolverTiming* gpu, double budget_us) {
  SolverChoice c;
  c.timings.push_back(cpu);
  if (gpu != nullptr) c.timings.push_back(*gpu);
  const std::string budget = "budget " + us(budget_us);
  if (gpu == nullptr) {
    c.name = cpu.name;
    c.why = "no GPU solver in this build: " + cpu.name + " (p99 " + us(cpu.p99_us) + ", " + budget + ")";
    return c;
  }
  if (!gpu->available) {
    c.name = cpu.name;
    c.why = gpu->name + " unavailable (" + gpu->reason + "): " + cpu.name + " (p99 " + us(cpu.p99_us) + ", " + budget + ")";
    return c;
  }
  const bool gpu_fits = gpu->p99_us <= budget_us, cpu_fits = cpu.available && cpu.p99_us <= budget_us;
  const std::string both = gpu->name + " p99 " + us(gpu->p99_us) + ", " + cpu.name + " p99 " +
                           (cpu.available ? us(cpu.p99_us) : "unavailable (" + cpu.reason + ")") + ", " + budget;
  if (gpu_fits && (!cpu_fits || gpu->p99_us <= cpu.p99_us)) {
    c.name = gpu->name;
    c.why = "the GPU fits the budget at least as well: " + both;
  } else if (cpu_fits) {
    c.name = cpu.name;
    c.why = gpu_fits ? "the CPU fits the budget better: " + both : "only the CPU fits the budget: " + both;
  } else {
    c.name = (!cpu.available || gpu->p99_us < cpu.p99_us) ? gpu->name : cpu.name;
    c.why = "neither fits the budget (late periods will fly the LQR fallback), the faster: " + both;
  }
  return c;
}

SolverTiming time_solver(const std::string& name, const ControllerArtifact& a, bool offset_free, int samples) {
  SolverTiming t;
  t.name = name;
  try {
    SolverOptions o;
    std::unique_ptr<QpSolver> s = make_controller_solver(name, a, o, "", offset_free);
    const int np = static_cast<int>(s->problem().nx());
    Eigen::VectorXd theta = Eigen::VectorXd::Zero(np);
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd dir = Eigen::VectorXd::Zero(a.n);
    std::vector<double> times;
    times.reserve(static_cast<std::size_t>(std::max(samples, 0)));
    const int warmup = std::max(1, samples / 10);
    for (int k = 0; k < warmup + samples; ++k) {
      // A slow walk through the set: consecutive states near each other, as in flight.
      for (int i = 0; i < a.n; ++i) dir(i) = std::clamp(dir(i) + 0.2 * u(rng), -1.0, 1.0);
      theta.head(a.n) = 0.03 * dir.cwiseProduct(a.x_bar.hi);
      const auto t0 = std::chrono::steady_clock::now();
      const SolveResult& r = s->solve(theta);
      const auto t1 = std::chrono::steady_clock::now();
      if (r.status != SolveStatus::Converged) {
        t.reason = "calibration solve " + std::to_string(k) + " ended " + to_string(r.status);
        return t;
      }
      if (k >= warmup) times.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    if (times.empty()) {
      t.reason = "no calibration samples";
      return t;
    }
    t.samples = static_cast<int>(times.size());
    t.p50_us = percentile(times, 0.5);
    t.p99_us = percentile(times, 0.99);
    t.max_us = percentile(times, 1.0);
    t.available = true;
  } catch (const std::exception& e) {
    t.reason = e.what();
  }
  return t;
}

std::string cpu_solver_name() { return "active-set"; }

std::string gpu_solver_name() {
  for (const std::string& n : solver_names()) {
    if (n == "admm-cuda") return n;
  }
  return "";
}

SolverChoice auto_solver(const ControllerArtifact& a, bool offset_free, double deadline_fraction, int samples) {
  const double budget_us = deadline_fraction * a.sample_time * 1e6;
  const SolverTiming cpu = time_solver(cpu_solver_name(), a, offset_free, samples);
  const std::string g = gpu_solver_name();
  if (g.empty()) return choose_solver(cpu, nullptr, budget_us);
  const SolverTiming gpu = time_solver(g, a, offset_free, samples);
  return choose_solver(cpu, &gpu, budget_us);
}

}  // namespace tmpc
