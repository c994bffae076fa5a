// The case-study controller of the solver tests and the nominal states its QPs are
// built at (shared by the CPU solver tests and the GPU parity tests).
#pragma once

#include <random>
#include <vector>

#include "../synthesis/design_fixture.hpp"

namespace tmpc::test {

inline const ControllerArtifact& case_study_artifact() {
  static const ControllerArtifact& a = quick_artifact();
  return a;
}

/// Nominal states inside the tightened state set: 3 % of its half-width in every one
/// of the 24 states at once (much larger simultaneous errors make the nominal QP
/// infeasible: the thesis' problem has no terminal set guaranteeing feasibility).
inline std::vector<Eigen::VectorXd> case_study_states(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs;
  const Eigen::VectorXd& hi = case_study_artifact().x_bar.hi;
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd x(hi.size());
    for (Eigen::Index i = 0; i < hi.size(); ++i) x(i) = 0.03 * u(rng) * hi(i);
    xs.push_back(x);
  }
  return xs;
}

}  // namespace tmpc::test
