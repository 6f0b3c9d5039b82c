// Placeholder until the implementation lands: fails loudly rather than linking to nothing.
#include <polyloc/io/recording.hpp>

namespace polyloc {
std::unique_ptr<RecordingWriter> createMcap(const std::string& path, const McapWriteOptions&) { throw IoError(path + ": MCAP writing is not implemented yet"); }
}  // namespace polyloc
