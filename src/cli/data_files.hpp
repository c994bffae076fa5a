// Where the CLI finds its shipped data (the default configuration and scenarios) when a
// path is left at its default: relative to the working directory when it is there
// (a checkout), else under $TMPC_DATA_DIR, else under the data folder compiled in
// (TMPC_DATA_DIR: the source tree of this build, or the install's share/tmpc).
#pragma once

#include <string>

namespace tmpc::cli {

/// `relative` (e.g. "config/scenarios/thesis_helix.yaml") where it exists, else the
/// first of the data folders above that holds it, else `relative` unchanged (the
/// loader then names it in its error).
std::string data_file(const std::string& relative);

}  // namespace tmpc::cli
