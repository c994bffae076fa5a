// `--solver auto` for the commands that fly (see runtime/solver_choice.hpp).
#include <cstdio>

#include "commands.hpp"
#include "tmpc/runtime/solver_choice.hpp"
#include "tmpc/runtime/tube_controller.hpp"

namespace tmpc::cli {

std::vector<std::string> flight_solver_choices() {
  std::vector<std::string> names = solver_choices();
  names.insert(names.begin(), "auto");
  return names;
}

std::string flight_solver_help() {
  return "auto (default: the GPU solver if a device answers and its calibrated p99 fits the deadline at least as "
         "well as the CPU's, else active-set) | " + solver_choices_help();
}

std::string resolve_solver(const std::string& name, const ControllerArtifact& a, const std::string& tube_law,
                           double deadline_fraction, const char* who, std::string* why) {
  if (name != "auto") return name;
  const bool offset_free = tube_law_options(a, tube_law).offset_free;
  const SolverChoice c = auto_solver(a, offset_free, deadline_fraction);
  std::fprintf(stderr, "%s: --solver auto: %s, because %s\n", who, c.name.c_str(), c.why.c_str());
  if (why != nullptr) *why = c.why;
  return c.name;
}

}  // namespace tmpc::cli
