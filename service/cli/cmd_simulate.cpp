#include "cli/commands.hpp"

namespace polyloc::cli {

void registerSimulate(CLI::App& app) {}  // placeholder: being written

}  // namespace polyloc::cli
