// Explicit MPC on the case study (the config's explicit horizon and box): the offline
// build (regions, seconds, memory) and the online point location, median/p99/max over
// states inside the partition, for the thesis' scan (1 and 2 OpenMP threads) and the
// search tree, against the exact ADMM warm solve of the online QP (N = 20) in the same run.
#include <chrono>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "bench_main.hpp"
#include "case_study.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/explicit/explicit_solver.hpp"

namespace {

const tmpc::ExplicitLaw& law() {
  static const tmpc::ExplicitLaw l = [] {
    const tmpc::ExplicitSettings e = tmpc::load_config(std::string(TMPC_SOURCE_DIR) + "/config/tiltrotor.yaml").explicit_mpc;
    tmpc::ExplicitOptions o;
    o.N = e.horizon;
    o.M = e.control_horizon;
    o.domain_fraction = e.domain_fraction;
    return tmpc::build_explicit_law(bench_case::artifact(), o);
  }();
  return l;
}

/// States inside the partition: uniform samples of the box that some region holds.
const std::vector<Eigen::VectorXd>& inside_states() {
  static const std::vector<Eigen::VectorXd> xs = [] {
    const tmpc::RegionScan scan(law().table, 1);
    std::mt19937_64 rng(5);
    std::vector<Eigen::VectorXd> v;
    Eigen::VectorXd th(law().n);
    while (v.size() < 2000) {
      for (int j = 0; j < law().n; ++j) {
        th(j) = std::uniform_real_distribution<double>(law().domain.lo(j), law().domain.hi(j))(rng);
      }
      if (scan.locate(th) >= 0) v.push_back(th);
    }
    return v;
  }();
  return xs;
}

void build(benchmark::State& st) {
  for (auto _ : st) benchmark::DoNotOptimize(law().regions());
  const tmpc::ExplicitLaw& l = law();
  st.counters["regions"] = l.regions();
  st.counters["complete"] = l.stats.complete;
  st.counters["build_s"] = l.stats.seconds;
  st.counters["tree_s"] = l.tree.stats.seconds;
  st.counters["tree_depth"] = l.tree.stats.depth;
  st.counters["tree_nodes"] = l.tree.stats.nodes;
  st.counters["halfspaces_per_region"] = static_cast<double>(l.table.k.size()) / l.regions();
  st.counters["memory_KiB"] = static_cast<double>(l.memory_bytes()) / 1024.0;
}

template <class Locate>
void locate(benchmark::State& st, Locate&& f) {
  const auto& xs = inside_states();
  std::vector<double> times;
  std::size_t k = 0;
  int found = 0;
  for (auto _ : st) {
    const Eigen::VectorXd& x = xs[k++ % xs.size()];
    const auto t0 = std::chrono::steady_clock::now();
    const int r = f(x);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(r);
    found += r >= 0;
    times.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  st.counters["located_pct"] = 100.0 * found / static_cast<double>(times.size());
  bench_case::time_counters(st, std::move(times));
}

void register_all() {
  benchmark::RegisterBenchmark("Explicit/build", build)->Iterations(1)->Unit(benchmark::kMillisecond);
  for (int threads : {1, 2}) {
    const std::string name = "Locate/scan/threads:" + std::to_string(threads);
    benchmark::RegisterBenchmark(name.c_str(), [threads](benchmark::State& st) {
      const tmpc::RegionScan scan(law().table, threads);
      locate(st, [&](const Eigen::VectorXd& x) { return scan.locate(x); });
    })->Iterations(20000)->Unit(benchmark::kMicrosecond);
  }
  benchmark::RegisterBenchmark("Locate/tree", [](benchmark::State& st) {
    locate(st, [&](const Eigen::VectorXd& x) { return law().tree.locate(law().table, x); });
  })->Iterations(20000)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("Solve/explicit/tree", [](benchmark::State& st) {
    auto s = tmpc::make_explicit_solver(bench_case::artifact(), law());
    locate(st, [&](const Eigen::VectorXd& x) { return static_cast<int>(s->solve(x).status); });
  })->Iterations(20000)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("Solve/admm/N20/warm", [](benchmark::State& st) {
    const tmpc::MpcQpData d = bench_case::data_for(20);
    auto s = tmpc::make_solver("admm", d);
    const std::vector<Eigen::VectorXd> xs = bench_case::warm_states(d, 200);
    std::vector<double> times;
    std::size_t k = 0;
    for (auto _ : st) times.push_back(s->solve(xs[k++ % xs.size()]).solve_us);
    bench_case::time_counters(st, std::move(times));
  })->Iterations(400)->Unit(benchmark::kMicrosecond);
}

}  // namespace

int main(int argc, char** argv) { return bench_case::run_registered(argc, argv, register_all); }
