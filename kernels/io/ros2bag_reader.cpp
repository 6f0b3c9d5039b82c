// Placeholder until the implementation lands: fails loudly rather than linking to nothing.
#include <polyloc/io/recording.hpp>

namespace polyloc {
std::unique_ptr<RecordingReader> openRos2Bag(const std::string& path) { throw IoError(path + ": ROS 2 bag reading is not implemented yet"); }
}  // namespace polyloc
