#include <set>

#include <gtest/gtest.h>

#include "../model/test_support.hpp"
#include "tmpc/model/perturbation.hpp"

namespace tmpc {
namespace {

std::array<double, 6> factors(const MassScaling& m) {
  return {m.load_mass, m.load_inertia, m.body_mass, m.body_inertia, m.rotor_mass, m.rotor_inertia};
}

TEST(Perturbation, ReproducibleBoundedAndDistinctPerRun) {
  PerturbationSettings s{0.10, "uniform", 1, 10};  // the thesis Monte Carlo (scenarios/thesis_helix.yaml)
  for (const char* dist : {"uniform", "normal"}) {
    s.distribution = dist;
    std::set<double> seen;
    for (int run = 0; run < 10; ++run) {
      const auto a = factors(draw_mass_scaling(s, run));
      const auto b = factors(draw_mass_scaling(s, run));
      EXPECT_EQ(a, b);
      for (double f : a) {
        EXPECT_GE(f, 1.0 - s.fraction);
        EXPECT_LE(f, 1.0 + s.fraction);
        seen.insert(f);
      }
    }
    EXPECT_EQ(seen.size(), 60u) << dist;
  }
}

TEST(Perturbation, AppliesToMassesAndInertias) {
  const VehicleParams& p = test::default_config().vehicle;
  MassScaling m;
  m.body_mass = 1.1;
  m.rotor_inertia = 0.9;
  const VehicleParams q = apply_mass_scaling(p, m);
  EXPECT_DOUBLE_EQ(q.body_mass, 1.1 * p.body_mass);
  EXPECT_DOUBLE_EQ(q.rotor_inertia(2, 2), 0.9 * p.rotor_inertia(2, 2));
  EXPECT_DOUBLE_EQ(q.load_mass, p.load_mass);
}

}  // namespace
}  // namespace tmpc
