// A quick design of the case study for tests: LQR tube gain without the LMI
// comparison (the LMI tests solve their own SDPs) and fewer check directions.
#pragma once

#include <fstream>
#include <sstream>

#include "../model/test_support.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/design.hpp"

namespace tmpc::test {

inline std::string default_config_text() {
  std::ifstream in(source_dir() + "/config/tiltrotor.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline Config quick_config() {
  Config c = default_config();
  c.synthesis.compare_gains = false;
  c.synthesis.verify_directions = 200;
  return c;
}

inline const ControllerDesign& quick_design() {
  static const ControllerDesign d = design_controller(quick_config(), default_config_text());
  return d;
}

}  // namespace tmpc::test
