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

}  // namespace tmpc::test
