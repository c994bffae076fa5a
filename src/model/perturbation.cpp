#include "tmpc/model/perturbation.hpp"

#include <algorithm>
#include <random>

namespace tmpc {

MassScaling draw_mass_scaling(const PerturbationSettings& s, int run) {
  // One independent stream per run: seed and run index through seed_seq.
  std::seed_seq seq{s.seed, static_cast<unsigned>(run), 0x746d7063u};
  std::mt19937_64 rng(seq);
  const double f = s.fraction;
  auto draw = [&]() {
    if (s.distribution == "normal") {
      std::normal_distribution<double> n(0.0, f / 3.0);
      return 1.0 + std::clamp(n(rng), -f, f);
    }
    std::uniform_real_distribution<double> u(-f, f);
    return 1.0 + u(rng);
  };
  MassScaling m;
  m.load_mass = draw();
  m.load_inertia = draw();
  m.body_mass = draw();
  m.body_inertia = draw();
  m.rotor_mass = draw();
  m.rotor_inertia = draw();
  return m;
}

VehicleParams apply_mass_scaling(const VehicleParams& p, const MassScaling& s) {
  VehicleParams out = p;
  out.load_mass *= s.load_mass;
  out.load_inertia *= s.load_inertia;
  out.body_mass *= s.body_mass;
  out.body_inertia *= s.body_inertia;
  out.rotor_mass *= s.rotor_mass;
  out.rotor_inertia *= s.rotor_inertia;
  return out;
}

}  // namespace tmpc
