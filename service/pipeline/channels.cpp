#include "pipeline/channels.hpp"

#include <fmt/core.h>

#include <stdexcept>

namespace polyloc::pipeline {

ChannelTable channelTable(const Rig& rig, const VrsConfig& vrs, uint32_t slots) {
  ChannelTable t;
  auto add = [&](shm::ChannelSpec s) {
    if (s.name.size() >= POLYLOC_NAME_LEN)
      throw std::invalid_argument(fmt::format("channel name '{}' is longer than {} characters", s.name, POLYLOC_NAME_LEN - 1));
    t.specs.push_back(std::move(s));
    return int(t.specs.size()) - 1;
  };
  for (size_t k = 0; k < rig.size(); ++k) {
    const Sensor& s = rig.sensors[k];
    shm::ChannelSpec c;
    c.direction = POLYLOC_DIR_INPUT, c.slot_count = slots, c.sensor = int32_t(k);
    if (const auto* cam = std::get_if<DepthCameraSpec>(&s.spec)) {
      c.name = "depth/" + s.name, c.kind = POLYLOC_KIND_DEPTH;
      c.width = uint32_t(cam->width), c.height = uint32_t(cam->height), c.count = c.width * c.height;
    } else {
      c.name = "scan/" + s.name, c.kind = POLYLOC_KIND_RANGES, c.count = uint32_t(s.beams().size());
    }
    t.sensor_channel.push_back(add(c));
    t.inputs.push_back(t.sensor_channel.back());
  }
  // Odometry comes faster than any scanner: more slots, so a slow cycle does not lose it.
  t.odom = add({.name = "odom", .kind = POLYLOC_KIND_ODOMETRY, .direction = POLYLOC_DIR_INPUT, .slot_count = 4 * slots});
  t.inputs.push_back(t.odom);
  if (t.inputs.size() > POLYLOC_MAX_INPUTS)
    throw std::invalid_argument(fmt::format("rig '{}' has {} sensors; polylocd takes at most {}", rig.name, rig.size(), POLYLOC_MAX_INPUTS - 1));
  // The controller's commands for the base: hosted here (one segment for the robot), never read
  // by polylocd, so not among its inputs (no health entry, no silence warning without a controller).
  t.command = add({.name = "cmd_vel", .kind = POLYLOC_KIND_COMMAND, .direction = POLYLOC_DIR_INPUT, .slot_count = slots});
  t.pose = add({.name = "pose", .kind = POLYLOC_KIND_POSE, .direction = POLYLOC_DIR_OUTPUT, .slot_count = slots});
  t.vrs = add({.name = "vrs", .kind = POLYLOC_KIND_VRS, .direction = POLYLOC_DIR_OUTPUT, .slot_count = slots,
               .count = uint32_t(vrs.segments())});
  t.tracks = add({.name = "tracks", .kind = POLYLOC_KIND_TRACKS, .direction = POLYLOC_DIR_OUTPUT, .slot_count = slots});
  t.health = add({.name = "health", .kind = POLYLOC_KIND_HEALTH, .direction = POLYLOC_DIR_OUTPUT, .slot_count = 4});
  return t;
}

std::vector<std::string> ChannelTable::inputNames() const {
  std::vector<std::string> names;
  for (int ch : inputs) names.push_back(specs[size_t(ch)].name);
  return names;
}

}  // namespace polyloc::pipeline
