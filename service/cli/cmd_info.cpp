#include "cli/commands.hpp"

namespace polyloc::cli {

void registerInfo(CLI::App& app) {}  // placeholder: being written

}  // namespace polyloc::cli
