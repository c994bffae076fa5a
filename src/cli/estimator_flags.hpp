// The estimator's flags of the commands that fly (simulate, controller, hil): one set,
// so that a flight simulated with an estimator is flown on the link with the same one.
#pragma once

#include <CLI/CLI.hpp>

#include "tmpc/runtime/estimator_choice.hpp"

namespace tmpc::cli {

/// --observer, --observer-gain, --fixed-filter-gain, --no-innovation-gate,
/// --no-step-detection and --step-keeps-lift on `sub`, into `e` (which must outlive
/// the parse).
void add_estimator_flags(CLI::App* sub, EstimatorChoice& e);

}  // namespace tmpc::cli
