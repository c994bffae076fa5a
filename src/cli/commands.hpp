// Subcommands of the tmpc executable; each registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace tmpc::cli {

/// `tmpc model --config FILE [--json]`: equilibrium, feedforward, linear error model.
void register_model(CLI::App& app);

/// `tmpc openloop` and `tmpc crosscheck`: commands that run a plant.
void register_plant(CLI::App& app);

/// `tmpc design`, `tmpc inspect`, `tmpc export-qp`: offline synthesis.
void register_design(CLI::App& app);

/// `tmpc solve`: one nominal QP with any solver.
void register_solve(CLI::App& app);

/// `tmpc simulate`: closed-loop helix mission on a virtual clock.
void register_simulate(CLI::App& app);

/// `tmpc devices`: CUDA devices available to this build.
void register_devices(CLI::App& app);

}  // namespace tmpc::cli
