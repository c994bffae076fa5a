// Subcommands of the tmpc executable; each registers itself on the CLI11 app.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tmpc::cli {

/// The main job's scenario, relative to the repository (or the install's share folder).
constexpr const char* kDefaultScenario = "config/scenarios/thesis_helix.yaml";
/// --yaw-into-force (simulate, controller, hil): runtime/yaw_governor.hpp.
constexpr const char* kYawIntoForceHelp =
    "the mission's yaw is free: turn the reference's yaw so that the force on the load lies on the box's diagonal "
    "(runtime/yaw_governor.hpp; an any-yaw design)";

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
/// What `tmpc devices` prints, a line each; `usable`: a CUDA device answered.
std::vector<std::string> device_lines(bool* usable);
/// `tmpc doctor`: the board's real-time set-up (runtime/doctor.hpp).
void register_doctor(CLI::App& app);
void register_explicit(CLI::App& app);
void register_compare(CLI::App& app);
void register_realtime(CLI::App& app);
/// `tmpc check`: a scenario's trajectory against an artifact's envelope, before flight.
void register_check(CLI::App& app);

/// The names --solver accepts: every QP solver of this build, then "explicit".
std::vector<std::string> solver_choices();
/// The same as "a | b | ..." for help texts.
std::string solver_choices_help();
/// --solver of the commands that fly (controller, hil, simulate): "auto" and solver_choices().
std::vector<std::string> flight_solver_choices();
std::string flight_solver_help();
}  // namespace tmpc::cli

namespace tmpc {
struct ControllerArtifact;
}

namespace tmpc::cli {
/// `name`, or for "auto" the solver runtime/solver_choice.hpp chooses for this artifact
/// and tube law (said on stderr, prefixed by `who`; the reason into `why`).
std::string resolve_solver(const std::string& name, const ControllerArtifact& a, const std::string& tube_law,
                           double deadline_fraction, const char* who, std::string* why = nullptr);

}  // namespace tmpc::cli

namespace tmpc {
struct ExplicitSettings;
struct ExplicitOptions;
struct ExplicitLaw;
}  // namespace tmpc

namespace tmpc::cli {
// Shared by `tmpc explicit` and `tmpc design --explicit` (cmd_explicit.cpp).
ExplicitOptions explicit_options_from(const ExplicitSettings& e);
void print_explicit_summary(const ExplicitLaw& law, const std::string& path);
std::string explicit_summary_json(const ExplicitLaw& law);

}  // namespace tmpc::cli
