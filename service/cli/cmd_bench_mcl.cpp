#include "cli/commands.hpp"

namespace polyloc::cli {

void registerBenchMcl(CLI::App& bench) {}  // placeholder: being written

}  // namespace polyloc::cli
