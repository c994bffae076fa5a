// Cost of the model: f(x, u, d), its exact Jacobians, one 12 ms plant period
// (12 RK4 steps) and the whole error-model construction (offline).
#include <benchmark/benchmark.h>

#include "tmpc/model/config.hpp"
#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/error_model.hpp"
#include "tmpc/sim/el_plant.hpp"

namespace {

const tmpc::Config& config() {
  static const tmpc::Config c = tmpc::load_config(std::string(TMPC_SOURCE_DIR) + "/config/tiltrotor.yaml");
  return c;
}

tmpc::State20 hover_state(const tmpc::TiltrotorModel& m, Eigen::Vector4d& u) {
  const tmpc::Equilibrium eq = tmpc::solve_hover_equilibrium(m);
  u = eq.u;
  tmpc::State20 x;
  x << eq.q(), tmpc::Vec10::Constant(0.01);
  return x;
}

void BM_StateDerivative(benchmark::State& st) {
  const tmpc::TiltrotorModel m(config().vehicle);
  Eigen::Vector4d u;
  const tmpc::State20 x = hover_state(m, u);
  for (auto _ : st) benchmark::DoNotOptimize(m.state_derivative(x, u, Eigen::Vector3d::Zero()));
}
BENCHMARK(BM_StateDerivative)->Unit(benchmark::kMicrosecond);

void BM_Linearize(benchmark::State& st) {
  const tmpc::TiltrotorModel m(config().vehicle);
  Eigen::Vector4d u;
  const tmpc::State20 x = hover_state(m, u);
  for (auto _ : st) benchmark::DoNotOptimize(m.linearize(x, u, Eigen::Vector3d::Zero()));
}
BENCHMARK(BM_Linearize)->Unit(benchmark::kMicrosecond);

void BM_PlantPeriod(benchmark::State& st) {
  tmpc::ElPlant plant(config().vehicle, tmpc::DisturbanceProfile{}, config().simulation.substep);
  Eigen::Vector4d u;
  const tmpc::State20 x = hover_state(plant.model(), u);
  plant.reset(x, 0.0);
  for (auto _ : st) plant.advance(u, config().sample_time);
}
BENCHMARK(BM_PlantPeriod)->Unit(benchmark::kMicrosecond);

void BM_BuildErrorModel(benchmark::State& st) {
  for (auto _ : st) benchmark::DoNotOptimize(tmpc::build_error_model(config()));
}
BENCHMARK(BM_BuildErrorModel)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
