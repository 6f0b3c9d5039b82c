#include "cli/commands.hpp"

namespace polyloc::cli {

void registerLocalize(CLI::App& app) {}  // placeholder: being written

}  // namespace polyloc::cli
