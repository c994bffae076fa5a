// What the link's safety costs the real-time loop per period (issue: input safety):
// decoding one state frame (COBS, CRC, version, session, sequence, finite, bounds),
// the state gate's time and jump tests (a one-period prediction with the 20-state
// error model), and the reference point the gate needs (the trim along the helix,
// which the law needs anyway). All in the loop's thread, allocation-free.
#include <benchmark/benchmark.h>

#include <vector>

#include "case_study.hpp"
#include "tmpc/io/protocol.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/reference_source.hpp"
#include "tmpc/runtime/state_gate.hpp"
#include "tmpc/runtime/tracking_error.hpp"

namespace {

using bench_case::artifact;

const tmpc::Config& config() {
  static const tmpc::Config c = tmpc::load_config(bench_case::source_dir() + "/config/tiltrotor.yaml");
  return c;
}

/// The thesis' helix (config/scenarios/thesis_helix.yaml).
std::shared_ptr<const tmpc::Trajectory> helix() {
  static const std::shared_ptr<const tmpc::Trajectory> h =
      tmpc::make_helix({Eigen::Vector3d(0, 0, 4), 5.0, 3.0, M_PI / 40.0, 0.0});
  return h;
}

/// Frames of the plant on the helix, one a period.
std::vector<std::vector<std::uint8_t>> frames(tmpc::ReferenceGenerator& traj, int count) {
  std::vector<std::vector<std::uint8_t>> out;
  for (int k = 0; k < count; ++k) {
    const double t = config().sample_time * k;
    const tmpc::ReferencePoint r = traj.at(t);
    tmpc::io::StateFrame f;
    f.session = 7;
    f.seq = static_cast<std::uint32_t>(k + 1);
    f.time = t;
    f.n = 20;
    for (int i = 0; i < 10; ++i) {
      f.x[static_cast<std::size_t>(i)] = r.q(i);
      f.x[static_cast<std::size_t>(10 + i)] = r.qd(i);
    }
    std::vector<std::uint8_t> b;
    tmpc::io::encode(f, b);
    out.push_back(b);
  }
  return out;
}

tmpc::StateGate make_gate() {
  const tmpc::ControllerArtifact& a = artifact();
  const std::vector<tmpc::StateKind> all = tmpc::tiltrotor_state_kinds();
  const std::vector<tmpc::StateKind> kinds(all.begin(), all.begin() + 20);
  return tmpc::StateGate(a.A.topLeftCorner(20, 20), a.B.topRows(20), a.N_x.head(20), a.N_u, kinds,
                         tmpc::state_gate_settings(config().link, kinds, a.N_x.head(20).cwiseInverse(), a.sample_time));
}

void BM_DecodeStateFrame(benchmark::State& st) {
  const tmpc::TiltrotorModel model(config().vehicle);
  tmpc::ReferenceGenerator traj(model, helix());
  const auto fs = frames(traj, 1000);
  const std::vector<tmpc::StateKind> all = tmpc::tiltrotor_state_kinds();
  tmpc::io::Decoder d(tmpc::state_decoder_settings(config().link, std::vector<tmpc::StateKind>(all.begin(), all.begin() + 20)));
  std::size_t k = 0;
  for (auto _ : st) {
    for (std::uint8_t b : fs[k]) benchmark::DoNotOptimize(d.push(b));
    if (++k == fs.size()) {
      k = 0;
      st.PauseTiming();
      d = tmpc::io::Decoder(d.settings());  // a fresh sequence
      st.ResumeTiming();
    }
  }
  st.counters["frame_bytes"] = static_cast<double>(fs[0].size());
}
BENCHMARK(BM_DecodeStateFrame)->Unit(benchmark::kMicrosecond);

void BM_StateGateCheck(benchmark::State& st) {
  tmpc::StateGate g = make_gate();
  // Measured errors of a flight near the reference (precomputed: the gate alone).
  std::vector<Eigen::VectorXd> errors;
  for (int k = 0; k < 1000; ++k) errors.push_back(Eigen::VectorXd::Constant(20, 1e-3 * std::sin(0.01 * k)));
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(4);
  long k = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(
        g.check(config().sample_time * static_cast<double>(k), static_cast<std::uint32_t>(k + 1), errors[static_cast<std::size_t>(k % 1000)], u));
    ++k;
  }
  st.counters["rejected"] = static_cast<double>(g.counts().rejected_total());
}
BENCHMARK(BM_StateGateCheck)->Unit(benchmark::kMicrosecond);

// One period's reference as the loop computes it: x_r and u_r from the artifact's
// records (the trim warm-started from the previous period's) and the measured error.
void BM_ReferencePointAndError(benchmark::State& st) {
  const tmpc::ControllerArtifact& a = artifact();
  auto ref = tmpc::make_reference_source(a, helix());
  const tmpc::TrackingError te(a.measured_kinds(), a.integrated);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(a.measured), x_r = e, x = e, u_r = Eigen::VectorXd::Zero(a.m);
  long k = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(ref->at(config().sample_time * static_cast<double>(k++), x_r, u_r));
    te.measured(x, x_r, e);
    benchmark::DoNotOptimize(e.data());
  }
}
BENCHMARK(BM_ReferencePointAndError)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
