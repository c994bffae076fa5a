// Flying a shipped scenario with the default (quick) artifact, printing what the
// README's scenario table states, for the scenario tests.
#pragma once

#include <cstdio>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/metrics/mission.hpp"

namespace tmpc::test {

inline const ControllerArtifact& artifact() {
  static const ControllerArtifact a = quick_artifact();
  return a;
}

inline MissionMetrics fly(const char* name, const ControllerArtifact& a = artifact()) {
  const MissionMetrics m = run_mission(a, shipped_scenario(name), MissionOptions{});
  std::printf("%s: RMSE", name);
  for (std::size_t i = 0; i < 3; ++i) std::printf(" %.3g", m.rmse[i]);
  std::printf(" (%s %s %s), %ld periods, violations %ld, fallbacks %ld, tube exits %ld%s\n", m.state_names[0].c_str(),
              m.state_names[1].c_str(), m.state_names[2].c_str(), m.periods, m.state_constraint_violations,
              m.fallback_periods, m.tube_exits, m.diverged ? ", DIVERGED" : "");
  return m;
}

/// The default artifact on its one-step residual observer alone (`--observer residual`:
/// the shipped design before its switched observer), printed like fly().
inline MissionMetrics fly_residual_observer(const char* name) {
  MissionOptions o;
  o.estimator.observer = "residual";
  const MissionMetrics m = run_mission(artifact(), shipped_scenario(name), o);
  std::printf("%s, residual observer alone: RMSE %.3g %.3g %.3g, violations %ld (worst %s %.2f), fallbacks %ld%s\n", name,
              m.rmse[0], m.rmse[1], m.rmse[2], m.state_constraint_violations, m.violation_worst_state.c_str(),
              m.violation_max_ratio, m.fallback_periods, m.diverged ? ", DIVERGED" : "");
  return m;
}

/// A scenario flown without the law's reversion past the model's region
/// (`--revert-beyond 0`: the softened MPC or the LQR fallback alone), printed like fly().
inline MissionMetrics fly_unreverted(const Scenario& sc, const ControllerArtifact& a = artifact()) {
  MissionOptions o;
  o.estimator.revert_beyond = 0.0;
  const MissionMetrics m = run_mission(a, sc, o);
  std::printf("without the reversion: RMSE %.3g %.3g %.3g, %ld periods, violations %ld, fallbacks %ld%s\n", m.rmse[0],
              m.rmse[1], m.rmse[2], m.periods, m.state_constraint_violations, m.fallback_periods,
              m.diverged ? ", DIVERGED" : "");
  return m;
}

}  // namespace tmpc::test
