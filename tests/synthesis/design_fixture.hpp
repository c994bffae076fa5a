// A quick design of the case study for tests: LQR tube gain without the LMI
// comparison (the LMI tests solve their own SDPs) and fewer check directions.
#pragma once

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "../model/test_support.hpp"
#include "tmpc/model/checksum.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/solvers/soft_penalty.hpp"
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

/// A shipped scenario by name (config/scenarios/NAME.yaml).
inline Scenario shipped_scenario(const std::string& name) {
  return load_scenario(source_dir() + "/config/scenarios/" + name + ".yaml");
}

/// The thesis mission without its force steps: the helix on the nominal plant.
inline Scenario quiet_helix() {
  Scenario s = shipped_scenario("thesis_helix");
  s.disturbances = DisturbanceProfile{};
  return s;
}

/// The second system (config/mass_spring.yaml: two masses on springs, 6 states with
/// the integrals, 2 inputs) designed through the same synthesis; a fraction of a second.
inline const ControllerArtifact& mass_spring_artifact() {
  static const ControllerArtifact a = [] {
    const std::string path = source_dir() + "/config/mass_spring.yaml";
    const std::string text = read_config_file(path, "configuration");
    const Config cfg = load_config_from_string(text, path);
    ControllerArtifact made = make_artifact(design_controller(cfg, text));
    apply_soft_penalty(made, cfg.soft_constraints.safety_factor);
    return made;
  }();
  return a;
}

/// The newest modification time of the libraries a design runs (TMPC_TEST_DESIGN_LIBS:
/// their paths, ':'-separated): a rebuilt library changes the design cache's key.
inline long design_libraries_stamp() {
  long newest = 0;
  std::stringstream paths(TMPC_TEST_DESIGN_LIBS);
  for (std::string path; std::getline(paths, path, ':');) {
    struct stat st {};
    if (!path.empty() && ::stat(path.c_str(), &st) == 0) newest = std::max(newest, static_cast<long>(st.st_mtime));
  }
  return newest;
}

/// An artifact designed once per build and shared by every test executable through the
/// build tree (TMPC_TEST_CACHE_DIR): ctest runs every test in its own process, and most
/// need only the artifact (a design takes seconds, a minute under the sanitizers). The
/// cache key is `tag`, the config text's CRC and the design libraries' newest
/// modification time, so a rebuilt library designs it anew; `make` designs it. Two
/// processes that miss at once both design and write the same file atomically.
///
/// With TMPC_TEST_ARTIFACTS=DIR in the environment, DIR/<tag>.tmpc is loaded instead
/// (scripts/cross_arm64.sh: the host's designs for tests run under emulation, where a
/// design takes many minutes; the loader's semantic checks still run on it).
template <class Make>
ControllerArtifact cached_artifact(const std::string& tag, const std::string& config_text, Make make) {
  if (const char* dir = std::getenv("TMPC_TEST_ARTIFACTS"); dir != nullptr && *dir != '\0') {
    return load_artifact(std::string(dir) + "/" + tag + ".tmpc");
  }
  const std::string key =
      std::to_string(crc32(reinterpret_cast<const std::uint8_t*>(config_text.data()), config_text.size())) + "-" +
      std::to_string(design_libraries_stamp());
  const std::string prefix = tag + "@";  // '@' is in no tag: "noisy@" is not a prefix of "noisy-tube@"
  const std::string path = std::string(TMPC_TEST_CACHE_DIR) + "/" + prefix + key + ".tmpc";
  try {
    return load_artifact(path);
  } catch (const ArtifactError&) {
  }
  ControllerArtifact made = make();
  // Earlier caches of `tag` (another config or build) are stale.
  if (DIR* dir = ::opendir(TMPC_TEST_CACHE_DIR)) {
    while (const dirent* e = ::readdir(dir)) {
      const std::string f = e->d_name;
      if (f.rfind(prefix, 0) == 0 && f.size() > 5 && f.compare(f.size() - 5, 5, ".tmpc") == 0 &&
          f != prefix + key + ".tmpc") {
        std::remove((std::string(TMPC_TEST_CACHE_DIR) + "/" + f).c_str());
      }
    }
    ::closedir(dir);
  }
  const std::string tmp = path + "." + std::to_string(::getpid());
  save_artifact(made, tmp);
  std::rename(tmp.c_str(), path.c_str());  // atomic: a concurrent reader sees all or nothing
  return made;
}

/// A shipped configuration (config/NAME.yaml) designed quick like quick_config(),
/// cached like quick_artifact() under `tag`.
inline ControllerArtifact quick_shipped_artifact(const std::string& name, const std::string& tag) {
  const std::string path = source_dir() + "/config/" + name + ".yaml";
  const std::string text = read_config_text(path);
  return cached_artifact(tag, text, [&] {
    Config cfg = load_config_from_string(text, path);
    cfg.synthesis.compare_gains = false;
    cfg.synthesis.verify_directions = 200;
    ControllerArtifact made = make_artifact(design_controller(cfg, text));
    apply_soft_penalty(made, cfg.soft_constraints.safety_factor);
    return made;
  });
}

/// The noisy-sensor design (config/tiltrotor_noisy.yaml: the shipped design with the
/// Kalman filter always, no noise monitor, and input-rate weights).
inline const ControllerArtifact& noisy_artifact() {
  static const ControllerArtifact a = quick_shipped_artifact("tiltrotor_noisy", "noisy");
  return a;
}

/// The noisy-sensor design with the Gaussian output-feedback tube applied
/// (config/tiltrotor_noisy_tube.yaml).
inline const ControllerArtifact& noisy_tube_artifact() {
  static const ControllerArtifact a = quick_shipped_artifact("tiltrotor_noisy_tube", "noisy-tube");
  return a;
}

/// The quick design's artifact (quick_config()), cached in the build tree: the shipped
/// design (config/tiltrotor.yaml, the switched observer).
inline const ControllerArtifact& quick_artifact() {
  static const ControllerArtifact a = cached_artifact("quick", default_config_text(), [] {
    ControllerArtifact made = make_artifact(quick_design());
    apply_soft_penalty(made, quick_design().cfg.soft_constraints.safety_factor);
    return made;
  });
  return a;
}

}  // namespace tmpc::test
