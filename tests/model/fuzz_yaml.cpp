// libFuzzer target of the YAML loaders a user feeds tmpc (built when clang is available;
// see tests/model/check_fuzz_yaml.cmake): the first byte chooses the loader (even: a
// configuration, load_config_from_string; odd: a scenario, scenario_from_string, its CSV
// tracks resolved against config/scenarios), the rest is the text. Nothing may crash
// (ASan, UBSan), hang (libFuzzer's -timeout) or escape but ConfigError, which names the
// file and the key.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "tmpc/model/config.hpp"
#include "tmpc/sim/scenario.hpp"

#ifndef TMPC_SCENARIO_DIR
#error "TMPC_SCENARIO_DIR: the folder the scenarios' CSV tracks resolve against"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] & 1) {
      tmpc::scenario_from_string(text, "fuzz.yaml", TMPC_SCENARIO_DIR);
    } else {
      tmpc::load_config_from_string(text, "fuzz.yaml");
    }
  } catch (const tmpc::ConfigError&) {
    return 0;  // refused with a message: fine
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_yaml: an exception other than ConfigError escaped: %s\n", e.what());
    __builtin_trap();
  }
  return 0;
}
