// Placeholder until the implementation lands: fails loudly rather than linking to nothing.
#include <polyloc/io/recording.hpp>

namespace polyloc {
std::unique_ptr<RecordingReader> openMcap(const std::string& path) { throw IoError(path + ": MCAP reading is not implemented yet"); }
}  // namespace polyloc
