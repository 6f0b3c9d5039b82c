// payloadSize: the bytes one frame of a channel takes at most, from its kind and dimensions.
#include "shm/layout.hpp"
#include "shm/segment.hpp"

namespace polyloc::shm {

uint32_t payloadSize(const ChannelSpec& s) {
  const uint64_t pixels = s.width && s.height ? uint64_t{s.width} * s.height : s.count;
  uint64_t bytes = 0;
  switch (s.kind) {
    case POLYLOC_KIND_RANGES: bytes = offsetof(polyloc_ranges, ranges) + uint64_t{s.count} * sizeof(float); break;
    // Capacity for depth and amplitude: the writer decides per frame whether amplitude follows.
    case POLYLOC_KIND_DEPTH: bytes = offsetof(polyloc_depth, data) + 2 * pixels * sizeof(float); break;
    case POLYLOC_KIND_ODOMETRY: bytes = sizeof(polyloc_odometry); break;
    case POLYLOC_KIND_COMMAND: bytes = sizeof(polyloc_command); break;
    case POLYLOC_KIND_POSE: bytes = sizeof(polyloc_pose); break;
    case POLYLOC_KIND_VRS: bytes = offsetof(polyloc_vrs, ranges) + uint64_t{s.count} * sizeof(float); break;
    case POLYLOC_KIND_TRACKS: bytes = sizeof(polyloc_tracks); break;
    case POLYLOC_KIND_HEALTH: bytes = sizeof(polyloc_health); break;
    default:
      throw ShmError(ShmError::Errc::Argument,
                     "channel '" + s.name + "': unknown kind " + std::to_string(s.kind));
  }
  // A slot must fit a uint32 slot_size; 1 GiB per frame is far beyond any sensor.
  if (bytes > (1u << 30))
    throw ShmError(ShmError::Errc::Argument, "channel '" + s.name + "': a frame of " +
                                                 std::to_string(bytes) + " bytes exceeds 1 GiB");
  return static_cast<uint32_t>(bytes);
}

}  // namespace polyloc::shm
