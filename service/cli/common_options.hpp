// Options that many commands take, declared in one place: one meaning, one check and one style
// of help text per flag (--map is a mesh file that exists, --threads 0 means all cores, --seed
// a non-negative integer, --sensor-height a height in metres of rays or sensors above z = 0,
// --duration seconds of a scenario or source with 0 for all of it).
#pragma once

#include "cli/parse_number.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace polyloc::cli {

inline CLI::Option* addMapOption(CLI::App& c, std::string& map, const std::string& help = "Map file (OBJ, PLY, STL, glTF, DAE)") {
  return c.add_option("--map", map, help)->check(CLI::ExistingFile);
}

template <class T>
CLI::Option* addThreadsOption(CLI::App& c, T& threads, const std::string& help = "Worker threads (0 = all cores)") {
  return c.add_option("--threads", threads, help)->capture_default_str()->check(finiteRange(0, 4096));
}

template <class T>
CLI::Option* addSeedOption(CLI::App& c, T& seed, const std::string& help) {
  return c.add_option("--seed", seed, help)->check(finiteRange(0, 1.8e19));
}

inline CLI::Option* addSensorHeightOption(CLI::App& c, double& height, const std::string& help) {
  return c.add_option("--sensor-height", height, help)->capture_default_str()->check(finiteRange(-1e4, 1e4));
}

// `what`: "the scenario's" or "the source's"; 0 (the default) runs all of it.
inline CLI::Option* addDurationOption(CLI::App& c, double& seconds, const std::string& help, const std::string& what) {
  return c.add_option("--duration", seconds, help + " (0: all of " + what + ")")->capture_default_str()->check(finiteRange(0.0, 1e7));
}

}  // namespace polyloc::cli
