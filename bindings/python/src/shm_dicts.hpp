// polyloc.shm's dicts: channel tables, and the payload structs of the public ABI (polyloc_shm.h)
// to and from Python values. Written from the struct fields alone: a client of the ABI, as any
// other would be, not a user of polylocd's own conversions.
#pragma once

#include "common.hpp"

#include "shm/channel.hpp"
#include "shm/segment.hpp"

#include <polyloc_shm.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace polyloc::py {

const char* kindName(uint32_t kind);  // "ranges", "depth", ..., "unknown"
std::string channelName(const polyloc_channel_desc& d);
pb::dict channelDict(const polyloc_channel_desc& d);
pb::dict specDict(const shm::ChannelSpec& s);
// A spec for Segment.create from a dict (name and kind required); ValueError/TypeError naming the key.
shm::ChannelSpec toSpec(const pb::handle& obj);

// A frame as read into a dict (buf: untrusted bytes, arrays bounded by what they hold).
// inputs: the segment's input channel names in channel order (the keys of health's inputs).
pb::dict frameDict(const shm::FrameInfo& f, const std::vector<uint8_t>& buf, const polyloc_channel_desc& c,
                   const std::vector<std::string>& inputs);

// The fixed-size payloads of the Writer's write_* from their arguments (raising on bad ones).
polyloc_odometry odometryPayload(int64_t stamp_ns, const pb::handle& odom_T_base, const std::array<double, 3>& twist);
polyloc_command commandPayload(int64_t stamp_ns, const std::array<double, 3>& twist, const std::string& nav_state,
                               uint32_t goal, const std::string& status);
polyloc_pose posePayload(int64_t stamp_ns, const pb::handle& pose, const pb::handle& covariance, const std::string& status,
                         size_t particles, double ess, uint64_t updates, int64_t latency_ns, const pb::handle& map_odom);
polyloc_tracks tracksPayload(int64_t stamp_ns, const pb::dict& tracks);
// segment: its name, for the error on an input that is not one of `inputs`.
polyloc_health healthPayload(int64_t stamp_ns, const pb::dict& health, const std::vector<std::string>& inputs,
                             const std::string& segment);

}  // namespace polyloc::py
