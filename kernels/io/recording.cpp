// Placeholder until the implementation lands: fails loudly rather than linking to nothing.
#include <polyloc/io/recording.hpp>

namespace polyloc {
std::unique_ptr<RecordingReader> openRecording(const std::string& path) { throw IoError(path + ": reading recordings is not implemented yet"); }
}  // namespace polyloc
