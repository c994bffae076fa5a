// `--solver auto`: at start-up, time the GPU solver (where this build has one and a
// device answers) and the CPU default on the artifact's own QP, and fly the one that
// fits the optimizer's budget (deadline fraction x period) at least as well. The rule
// is choose_solver() (pure, tested with injected timings); time_solver() measures.
#pragma once

#include <string>
#include <vector>

#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

/// One candidate's calibration: wall-clock time of each solve() call (transfers and
/// kernel launches included), over states spread in the tightened state set.
struct SolverTiming {
  std::string name;
  bool available = false;  ///< built, a device answered, and every calibration solve converged
  std::string reason;      ///< why not available
  int samples = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;
};

struct SolverChoice {
  std::string name;                    ///< the solver to fly
  std::string why;                     ///< one line for the log and the telemetry header
  std::vector<SolverTiming> timings;   ///< CPU first, then the GPU's (if one was tried)
};

/// The GPU when it is available, its p99 fits `budget_us` and is no worse than the
/// CPU's p99 (or the CPU's does not fit); the CPU otherwise. Neither fitting: the
/// smaller p99, said so in `why`.
SolverChoice choose_solver(const SolverTiming& cpu, const SolverTiming* gpu, double budget_us);

/// Times `samples` solves of solver `name` in the runtime's form (offset-free or not)
/// on deterministic states at up to 3 % of the tightened state set's half-widths, one
/// after another (the warm starts of a flight), after `samples / 10` untimed ones.
/// Never throws for a solver that cannot be built or fails: available = false, reason.
SolverTiming time_solver(const std::string& name, const ControllerArtifact& a, bool offset_free, int samples = 200);

/// The CPU default: "active-set" (exact, 2-9x faster than admm on the QP sets of
/// bench/bench_solvers.cpp Sets/, README "Benchmarks").
std::string cpu_solver_name();

/// The GPU solver this build registered ("admm-cuda"), or "" without CUDA.
std::string gpu_solver_name();

/// time_solver() of cpu_solver_name() and of gpu_solver_name(), then choose_solver()
/// with the budget `deadline_fraction` x the artifact's sample time.
SolverChoice auto_solver(const ControllerArtifact& a, bool offset_free, double deadline_fraction, int samples = 200);

}  // namespace tmpc
