// polylocd's channel table, from the rig and the daemon settings (docs/interface.md lists it):
//   scan/<sensor>   input, RANGES: a planar scanner or lidar of the rig, its beam count
//   depth/<sensor>  input, DEPTH: a depth camera, its width x height, depth + amplitude
//   odom            input, ODOMETRY
//   cmd_vel         input, COMMAND: a controller's commands for the base (polylocd does not read it)
//   pose, vrs, tracks, health   outputs
#pragma once

#include "shm/segment.hpp"

#include <polyloc/sensors/rig.hpp>
#include <polyloc/vrs/config.hpp>

#include <string>
#include <vector>

namespace polyloc::pipeline {

struct ChannelTable {
  std::vector<shm::ChannelSpec> specs;
  int odom = -1, command = -1, pose = -1, vrs = -1, tracks = -1, health = -1;
  std::vector<int> inputs;          // channel indices of the inputs, in table order
  std::vector<int> sensor_channel;  // per rig sensor: its input channel

  std::vector<std::string> inputNames() const;  // of the inputs, in table order (health's order)
};

ChannelTable channelTable(const Rig& rig, const VrsConfig& vrs, uint32_t slots);

}  // namespace polyloc::pipeline
