#include "cli/renamed_options.hpp"

#include <fmt/core.h>

#include <set>

namespace polyloc::cli {

const std::vector<RenamedOption>& renamedOptions() {
  // --height was a sensor height in bench/demo and the robot's height in navgrid; --clearance a
  // robot radius in bench bsp and a floor clearance in navgrid; --grid a list of resolutions in
  // bench bsp and a map_server file everywhere else; --rounds a filter round in eval and a turn of
  // the transports in bench ipc.
  static const std::vector<RenamedOption> table{
      {"bench raycast", "--height", "--sensor-height"}, {"bench bsp", "--height", "--sensor-height"},
      {"bench maps", "--height", "--sensor-height"},    {"bench mcl", "--height", "--sensor-height"},
      {"demo", "--height", "--sensor-height"},          {"map navgrid", "--height", "--robot-height"},
      {"map navgrid", "--clearance", "--floor-clearance"}, {"bench bsp", "--clearance", "--robot-radius"},
      {"bench bsp", "--grid", "--grid-resolutions"},    {"bench ipc", "--rounds", "--turns"},
  };
  return table;
}

std::vector<std::string> applyRenames(int argc, const char* const* argv, std::FILE* warn) {
  std::vector<std::string> args(argv, argv + argc);
  // The subcommand path: the words before the first option.
  std::string command;
  for (int i = 1; i < argc && args[i].rfind('-', 0) != 0; ++i) command += (command.empty() ? "" : " ") + args[i];
  std::set<std::string> warned;
  for (size_t i = 1; i < args.size(); ++i) {
    std::string& a = args[i];
    if (a == "--") break;
    for (const RenamedOption& r : renamedOptions()) {
      const std::string old_name = r.old_name;
      if (command != r.command && command.rfind(std::string(r.command) + " ", 0) != 0) continue;
      if (a != old_name && a.rfind(old_name + "=", 0) != 0) continue;
      a = r.new_name + a.substr(old_name.size());
      if (warned.insert(old_name).second)
        fmt::print(warn, "polyloc {}: warning: {} is deprecated, use {} (same meaning)\n", r.command, old_name, r.new_name);
      break;
    }
  }
  return args;
}

}  // namespace polyloc::cli
