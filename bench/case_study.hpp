// The case study for the benchmarks: the default design (LQR tube gain, no gain
// comparison), its QP at horizon N, independent random states and a closed-loop-like
// state sequence.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "tmpc/model/config.hpp"
#include "tmpc/qp/redundant_rows.hpp"
#include "tmpc/solvers/solver.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/design.hpp"

namespace bench_case {

using tmpc::ControllerArtifact;

/// The source tree: $TMPC_SOURCE_DIR when set (a copy of the tree elsewhere, e.g. on
/// a GPU machine), else where this build's sources were.
inline std::string source_dir() {
  const char* env = std::getenv("TMPC_SOURCE_DIR");
  return env != nullptr && env[0] != '\0' ? std::string(env) : std::string(TMPC_SOURCE_DIR);
}

inline const ControllerArtifact& artifact() {
  static const ControllerArtifact a = [] {
    tmpc::Config c = tmpc::load_config(source_dir() + "/config/tiltrotor.yaml");
    c.synthesis.compare_gains = false;
    c.synthesis.verify_directions = 50;
    return tmpc::make_artifact(tmpc::design_controller(c, ""));
  }();
  return a;
}

/// The nominal QP at horizon N with its redundant rows certified (the artifact's own
/// record at its horizon, N = 20).
inline tmpc::MpcQpData data_for(int N) {
  const ControllerArtifact& a = artifact();
  if (N == a.N && std::min(4, N) == a.M) return a.qp();
  tmpc::MpcQpData d = tmpc::build_mpc_qp(a.A, a.B, a.Sigma_rho, a.Sigma_lambda, a.L, a.x_bar, a.u_bar, N, std::min(4, N));
  tmpc::certify_redundant_rows(d);
  return d;
}

inline std::vector<Eigen::VectorXd> cold_states(int count) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs;
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd x(24);
    for (int i = 0; i < 24; ++i) x(i) = 0.03 * u(rng) * artifact().x_bar.hi(i);
    xs.push_back(x);
  }
  return xs;
}

/// A closed-loop-like sequence: the nominal closed loop under the reference solver's
/// input plus a small random kick per step (the tube feedback's effect).
inline std::vector<Eigen::VectorXd> warm_states(const tmpc::MpcQpData& d, int count) {
  tmpc::SolverOptions o;
  o.warm_start = false;
  auto ref = tmpc::make_solver("reference", d, o);
  std::mt19937_64 rng(43);
  std::normal_distribution<double> g(0.0, 1e-4);
  Eigen::VectorXd x = cold_states(1)[0];
  std::vector<Eigen::VectorXd> xs;
  for (int k = 0; k < count; ++k) {
    xs.push_back(x);
    const Eigen::Vector4d u = ref->solve(x).u0();
    x = d.A * x + d.B * u;
    for (int i = 0; i < 24; ++i) x(i) += g(rng);
  }
  return xs;
}


/// Median, p99 and max of the samples as benchmark counters (us).
template <class State>
void time_counters(State& st, std::vector<double> times) {
  std::sort(times.begin(), times.end());
  auto pct = [&](double p) { return times[std::min(times.size() - 1, static_cast<std::size_t>(p * times.size()))]; };
  st.counters["median_us"] = pct(0.5);
  st.counters["p99_us"] = pct(0.99);
  st.counters["max_us"] = times.back();
}

}  // namespace bench_case
