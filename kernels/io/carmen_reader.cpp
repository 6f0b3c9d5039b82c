// Placeholder until the implementation lands: fails loudly rather than linking to nothing.
#include <polyloc/io/recording.hpp>

namespace polyloc {
std::unique_ptr<RecordingReader> openCarmen(const std::string& path) { throw IoError(path + ": CARMEN reading is not implemented yet"); }
}  // namespace polyloc
