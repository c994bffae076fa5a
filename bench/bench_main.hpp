// The main() of a benchmark executable whose benchmarks are registered at run time
// (names built from horizons, solvers, paths).
#pragma once

#include <benchmark/benchmark.h>

namespace bench_case {

inline int run_registered(int argc, char** argv, void (*register_all)()) {
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace bench_case
