// Monte Carlo perturbations of the plant (thesis 6.5): masses and inertias of the
// bodies scaled by independent factors in [1 - f, 1 + f], from a seeded RNG so a
// run is reproducible from (seed, run index).
#pragma once

#include <array>
#include <string>

#include "tmpc/model/config.hpp"

namespace tmpc {

/// Scale factors of one perturbed plant.
struct MassScaling {
  double load_mass = 1.0, load_inertia = 1.0;
  double body_mass = 1.0, body_inertia = 1.0;
  double rotor_mass = 1.0, rotor_inertia = 1.0;
};

/// Factors of run `run` (0-based) drawn with the settings' distribution and seed.
MassScaling draw_mass_scaling(const PerturbationSettings& s, int run);

/// Vehicle parameters with masses and inertias scaled.
VehicleParams apply_mass_scaling(const VehicleParams& p, const MassScaling& s);

}  // namespace tmpc
