// QP solve latency on the case study: every solver and variant, horizons N in
// {10, 20, 40} (M = 4), cold (independent random states) and warm (a closed-loop
// sequence). Counters: median, p99 and max solve time (us), mean, p99 and max
// iterations, the exact ADMM's mean active-set steps, the thesis variant's
// optimality gap against the reference (relative to the full cost), and the median
// and p99 over the states of each state's fastest pass (the work's own spread).
// OffsetFree/...: the default tube law's QP (parameter (x_bar - x_s, d_hat, c_hat),
// mpc_qp.hpp) at a 1 N force along x and a small model offset, against the same
// states' nominal QP in the same run.
#include <algorithm>
#include <map>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "bench_main.hpp"
#include "case_study.hpp"

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
    const tmpc::DisturbanceTarget t = artifact().disturbance_target();
    tmpc::make_offset_free(d, t.Tx, t.Tu);
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

/// Solves per benchmark: the exact ADMM's p99 rests on 100 samples (50 passes over
/// the 200 states, 0.2 to 0.5 s of solving, what the 83 Hz loop sees in two minutes;
/// this VM's timer tick adds ~25 us to about 0.5 % of 20 us solves and a burst of steal
/// time to a run of consecutive ones, which decided the p99 of 400 or 2000 samples),
/// the slow solvers' on one or two passes.
int samples(const std::string& solver) {
  if (solver == "admm") return 10000;
  return solver == "cz" || solver == "admm-thesis" ? 100 : 400;
}

void register_all() {
  for (int N : {10, 20, 40}) {
    for (const char* solver : {"admm", "admm-thesis", "cz", "reference"}) {
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
  for (const char* solver : {"admm", "reference"}) {
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
