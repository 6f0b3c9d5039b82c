// Placeholder until the implementation lands: fails loudly rather than linking to nothing.
#include <polyloc/io/cdr.hpp>

namespace polyloc::msg {

std::vector<uint8_t> encodeCdr(const Message&) { throw IoError("CDR encoding is not implemented yet"); }
Message decodeCdr(const std::string& type, std::span<const uint8_t>) { throw IoError(type + ": CDR decoding is not implemented yet"); }
const std::string& ros2msgSchema(const std::string& type) { throw IoError(type + ": no schema yet"); }

}  // namespace polyloc::msg
