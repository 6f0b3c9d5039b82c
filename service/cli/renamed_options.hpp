// Options that were renamed so that one name means one thing in every command: the old name still
// works for a while, rewritten to the new one before parsing, with a warning on stderr. The help
// shows only the new names.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace polyloc::cli {

struct RenamedOption {
  const char* command;   // the subcommand path it belongs to, e.g. "map navgrid"
  const char* old_name;  // e.g. "--height"
  const char* new_name;  // e.g. "--robot-height"
};

// Every rename still accepted (listed in README.md, "The CLI").
const std::vector<RenamedOption>& renamedOptions();

// argv with the old names of the invoked subcommand replaced by the new ones ("--old" and
// "--old=value" both); one warning per replaced name on `warn`. Tokens after "--" are left alone.
std::vector<std::string> applyRenames(int argc, const char* const* argv, std::FILE* warn);

}  // namespace polyloc::cli
