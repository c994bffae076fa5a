// QP solve latency on the case study: every solver and variant, horizons N in
// {10, 20, 40} (M = 4), cold (independent random states) and warm (a closed-loop
// sequence). Counters: median, p99 and max solve time (us), mean, p99 and max
// iterations, the exact ADMM's mean active-set steps, the thesis variant's
// optimality gap against the reference (relative to the full cost), and the median
// and p99 over the states of each state's fastest pass (the work's own spread).
// OffsetFree/...: the default tube law's QP (parameter (x_bar - x_s, d_hat, c_hat),
// mpc_qp.hpp) at a 1 N force along x and a small model offset, against the same
// states' nominal QP in the same run.
// Sets/: the three QP sets of the solver issue, each solver on the same instances:
//   mission  the QPs the default law (offset-free, 51 parameters) solved in 20 s of the
//            helix mission, recorded from the flight (MissionOptions::record_qps)
//   bench    the cold states above (3 % of the tightened box at once, nominal QP)
//   hard     along random directions at 50-95 % of the largest feasible scale (CLP
//            bisection), nominal QP
//   soft     the softened nominal QP (penalty 50) at 3-30 % of the box, most of them
//            infeasible as hard QPs (cold, caches hot)
// in order (warm: each solve warm-started from the one before), caches hot, and
// cache_cold: 48 MB written between solves (past this machine's L2 and L3).
#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "bench_main.hpp"
#include "case_study.hpp"
#include "tmpc/metrics/mission.hpp"
#include "tmpc/sets/lp.hpp"
#include "tmpc/sim/scenario.hpp"

namespace {

using bench_case::artifact;
using bench_case::cold_states;
using bench_case::data_for;
using bench_case::warm_states;

void run(benchmark::State& st, const std::string& solver, int N, bool warm, tmpc::SolverOptions o,
         bool offset_free = false) {
  const tmpc::MpcQpData nominal = data_for(N);
  tmpc::MpcQpData d = nominal;
  o.warm_start = warm;
  std::vector<Eigen::VectorXd> xs = warm ? warm_states(nominal, 200) : cold_states(200);
  if (offset_free) {
    d = artifact().qp(true);  // with its recorded certificate (N = 20)
    std::mt19937_64 rng(44);
    std::uniform_real_distribution<double> u(-1e-5, 1e-5);
    for (Eigen::VectorXd& x : xs) {
      Eigen::VectorXd theta(d.parameters());
      theta << x, 1.0, 0.0, 0.0, Eigen::VectorXd::Zero(24);
      for (int i = 0; i < 24; ++i) theta(27 + i) = u(rng);
      x = theta;
    }
  }
  auto s = tmpc::make_solver(solver, d, o);
  std::unique_ptr<tmpc::QpSolver> ref;
  const bool gap = solver == "admm-thesis";
  if (gap) {
    tmpc::SolverOptions ro;
    ro.warm_start = false;
    ref = tmpc::make_solver("reference", d, ro);
  }
  std::vector<double> times, its;
  double iters = 0.0, worst_gap = 0.0, steps = 0.0;
  int converged = 0;
  std::size_t k = 0;
  for (auto _ : st) {
    const Eigen::VectorXd& x = xs[k % xs.size()];
    const tmpc::SolveResult& r = s->solve(x);
    times.push_back(r.solve_us);
    iters += r.iterations;
    its.push_back(r.iterations);
    steps += r.active_set_steps;
    converged += r.status == tmpc::SolveStatus::Converged;
    if (gap && k < xs.size()) {
      st.PauseTiming();
      const double obj = r.objective;
      const double ref_obj = ref->solve(x).objective;
      const double V = tmpc::condensed_qp(d, x.head(24)).constant + ref_obj;
      worst_gap = std::max(worst_gap, (obj - ref_obj) / std::max(V, 1e-12));
      st.ResumeTiming();
    }
    ++k;
  }
  st.counters["iterations"] = iters / static_cast<double>(times.size());
  std::sort(its.begin(), its.end());
  st.counters["iterations_p99"] = its[std::min(its.size() - 1, its.size() * 99 / 100)];
  st.counters["iterations_max"] = its.back();
  if (solver == "admm") st.counters["active_set_steps"] = steps / static_cast<double>(times.size());
  st.counters["converged_pct"] = 100.0 * converged / static_cast<double>(times.size());
  if (gap) st.counters["thesis_gap"] = worst_gap;
  // The work's own tail, apart from the machine's: each state's fastest of its passes
  // (this VM's timer tick and steal time put a few identical warm solves at 2-5x).
  std::vector<double> best(std::min(times.size(), xs.size()), 1e300);
  for (std::size_t i = 0; i < times.size(); ++i) best[i % xs.size()] = std::min(best[i % xs.size()], times[i]);
  std::sort(best.begin(), best.end());
  st.counters["state_min_median_us"] = best[best.size() / 2];
  st.counters["state_min_p99_us"] = best[std::min(best.size() - 1, best.size() * 99 / 100)];
  bench_case::time_counters(st, std::move(times));
}

/// The largest common slack of the instance's rows (CLP): > 0 feasible.
double feasibility_slack(const tmpc::CondensedQp& qp) { return tmpc::largest_common_slack(qp.A, qp.lo, qp.hi); }

const std::vector<Eigen::VectorXd>& qp_set(const std::string& set) {
  static std::map<std::string, std::vector<Eigen::VectorXd>> sets;
  auto it = sets.find(set);
  if (it != sets.end()) return it->second;
  std::vector<Eigen::VectorXd> xs;
  if (set == "mission") {
    const tmpc::Scenario sc = tmpc::load_scenario(bench_case::source_dir() + "/config/scenarios/thesis_helix.yaml");
    tmpc::MissionOptions o;
    o.solver = "active-set";
    o.duration = 20.0;
    o.record_qps = &xs;
    tmpc::run_mission(artifact(), sc, o);
  } else if (set == "bench") {
    xs = cold_states(200);
  } else if (set == "soft") {
    // 3 % to 30 % of the box at once: most of these hard QPs are infeasible.
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 200; ++k) {
      Eigen::VectorXd x(24);
      for (int i = 0; i < 24; ++i) x(i) = (0.03 + 0.27 * (k % 10) / 9.0) * u(rng) * artifact().x_bar.hi(i);
      xs.push_back(x);
    }
  } else {
    const tmpc::ParametricQp qp = tmpc::ParametricQp::from_mpc(data_for(20));
    const Eigen::VectorXd& half = artifact().x_bar.hi;
    std::mt19937_64 rng(22);
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> frac(0.5, 0.95);
    while (xs.size() < 200) {
      Eigen::VectorXd dir(half.size());
      for (Eigen::Index i = 0; i < dir.size(); ++i) dir(i) = g(rng) * half(i);
      dir /= dir.cwiseQuotient(half).cwiseAbs().maxCoeff();
      if (feasibility_slack(qp.instance(dir)) > 0.0) continue;
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 30; ++it) {
        const double mid = 0.5 * (lo + hi);
        (feasibility_slack(qp.instance(mid * dir)) > 0.0 ? lo : hi) = mid;
      }
      xs.push_back(frac(rng) * lo * dir);
    }
  }
  return sets.emplace(set, std::move(xs)).first->second;
}

void run_set(benchmark::State& st, const std::string& solver, const std::string& set, bool warm, bool cache_cold) {
  tmpc::MpcQpData d = set == "mission" ? artifact().qp(true) : data_for(20);
  if (set == "soft") d.soft_penalty = 50.0;  // the softened QP (1000 rows)
  const std::vector<Eigen::VectorXd>& xs = qp_set(set);
  tmpc::SolverOptions o;
  o.warm_start = warm;
  const bool crash = solver == "admm-crash";
  o.crash_start = crash;
  auto s = tmpc::make_solver(crash ? "admm" : solver, d, o);
  std::vector<char> junk(cache_cold ? 48u << 20 : 0u);
  std::vector<double> times;
  int converged = 0, active = 0;
  double steps = 0.0;
  std::size_t k = 0;
  for (auto _ : st) {
    if (cache_cold) {
      st.PauseTiming();
      std::memset(junk.data(), static_cast<int>(k & 0xff), junk.size());
      benchmark::DoNotOptimize(junk.data());
      st.ResumeTiming();
    }
    const tmpc::SolveResult& r = s->solve(xs[k % xs.size()]);
    times.push_back(r.solve_us);
    converged += r.status == tmpc::SolveStatus::Converged;
    active += static_cast<int>((r.y.array() != 0.0).count());
    steps += r.iterations;
    ++k;
  }
  st.counters["iterations"] = steps / static_cast<double>(times.size());
  // The work's own spread, apart from the machine's: each instance's fastest pass.
  std::vector<double> best(std::min(times.size(), xs.size()), 1e300);
  for (std::size_t i = 0; i < times.size(); ++i) best[i % xs.size()] = std::min(best[i % xs.size()], times[i]);
  std::sort(best.begin(), best.end());
  st.counters["state_min_median_us"] = best[best.size() / 2];
  st.counters["state_min_p99_us"] = best[std::min(best.size() - 1, best.size() * 99 / 100)];
  st.counters["qps"] = static_cast<double>(xs.size());
  st.counters["converged_pct"] = 100.0 * converged / static_cast<double>(times.size());
  st.counters["active_rows_mean"] = active / static_cast<double>(times.size());
  bench_case::time_counters(st, std::move(times));
}

/// Solves per benchmark: the exact ADMM's p99 rests on 100 samples (50 passes over
/// the 200 states, 0.2 to 0.5 s of solving, what the 83 Hz loop sees in two minutes;
/// this VM's timer tick adds ~25 us to about 0.5 % of 20 us solves and a burst of steal
/// time to a run of consecutive ones, which decided the p99 of 400 or 2000 samples),
/// the slow solvers' on one or two passes.
int samples(const std::string& solver) {
  if (solver == "admm" || solver == "active-set") return 10000;
  return solver == "cz" || solver == "admm-thesis" ? 100 : 400;
}

void register_all() {
  for (const char* set : {"mission", "bench", "hard"}) {
    for (const char* solver : {"active-set", "admm", "admm-crash"}) {
      for (bool warm : {false, true}) {
        for (bool cold_cache : {false, true}) {
          const std::string name = std::string("Sets/") + set + "/" + solver + (warm ? "/warm" : "/cold") +
                                   (cold_cache ? "/cache_cold" : "/cache_hot");
          auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
            run_set(st, solver, set, warm, cold_cache);
          });
          b->Unit(benchmark::kMicrosecond)->Iterations(cold_cache ? 400 : 4000);
        }
      }
    }
  }
  for (const char* solver : {"active-set", "admm"}) {
    const std::string name = std::string("Sets/soft/") + solver + "/cold/cache_hot";
    auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
      run_set(st, solver, "soft", false, false);
    });
    b->Unit(benchmark::kMicrosecond)->Iterations(std::string(solver) == "admm" ? 200 : 2000);
  }
  for (int N : {10, 20, 40}) {
    for (const char* solver : {"admm", "admm-thesis", "cz", "reference", "active-set"}) {
      for (bool warm : {false, true}) {
        if (std::string(solver) == "reference" && warm) continue;  // an interior point has no warm start
        const std::string name = std::string("Solve/") + solver + "/N" + std::to_string(N) + (warm ? "/warm" : "/cold");
        auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
          run(st, solver, N, warm, tmpc::SolverOptions{});
        });
        b->Unit(benchmark::kMicrosecond)->Iterations(samples(solver));
      }
    }
  }
  for (const char* solver : {"admm", "reference", "active-set"}) {
    for (bool warm : {false, true}) {
      if (std::string(solver) == "reference" && warm) continue;
      const std::string name = std::string("OffsetFree/") + solver + "/N20" + (warm ? "/warm" : "/cold");
      auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
        run(st, solver, 20, warm, tmpc::SolverOptions{}, true);
      });
      b->Unit(benchmark::kMicrosecond)->Iterations(samples(solver));
    }
  }
  // The penalty rule, the acceleration and the active-set finish, exact ADMM at the
  // default horizon (the default is spectral_x0.1_adaptive: the finish from the first
  // check, at most 30 steps). no_polish is the ADMM alone; plain_polish the OSQP
  // polish (the guess taken as it is, no step); crash_start skips the iterations when
  // the start point's active set finishes.
  struct Variant {
    const char* name;
    double rho_scale;
    bool adaptive, nesterov, ruiz, polish;
    int steps, check_every;
    bool crash;
  };
  for (const Variant v : {Variant{"spectral_x1", 1.0, false, false, false, true, 30, 5, false},
                          Variant{"spectral_x0.1", 0.1, false, false, false, true, 30, 5, false},
                          Variant{"spectral_x0.1_adaptive", 0.1, true, false, false, true, 30, 5, false},
                          Variant{"spectral_x0.1_adaptive_nesterov", 0.1, true, true, false, true, 30, 5, false},
                          Variant{"spectral_x0.1_adaptive_ruiz", 0.1, true, false, true, true, 30, 5, false},
                          Variant{"no_polish", 0.1, true, false, false, false, 30, 5, false},
                          Variant{"plain_polish", 0.1, true, false, false, true, 0, 5, false},
                          Variant{"check_every1", 0.1, true, false, false, true, 30, 1, false},
                          Variant{"crash_start", 0.1, true, false, false, true, 30, 5, true}}) {
    for (bool warm : {false, true}) {
      const std::string name = std::string("Rho/admm/N20/") + v.name + (warm ? "/warm" : "/cold");
      auto* b = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) {
        tmpc::SolverOptions o;
        o.rho_scale = v.rho_scale;
        o.adaptive_rho = v.adaptive;
        o.nesterov = v.nesterov;
        o.equilibrate = v.ruiz;
        o.polish = v.polish;
        o.polish_steps = v.steps;
        o.check_every = v.check_every;
        o.crash_start = v.crash;
        run(st, "admm", 20, warm, o);
      });
      b->Unit(benchmark::kMicrosecond)->Iterations(samples("admm"));
    }
  }
}

}  // namespace

int main(int argc, char** argv) { return bench_case::run_registered(argc, argv, register_all); }
