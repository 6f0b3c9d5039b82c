// What polynav reads from polylocd, each input decoded and checked in one function: the program's
// loop holds no byte arithmetic, and what it does with a short slot or a failed read has tests.
// Over the C client only (polyloc_client.h), as any controller of a user's would read it.
#pragma once

#include <polyloc_client.h>
#include <polynav/polar_scan.hpp>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace polynav {

struct VrsFrame {
  int64_t stamp_ns = 0;
  PolarScan scan;  // angles at the segments' centres
};

// A VRS slot of `size` bytes as polylocd wrote it. nullopt (and *why) when the slot cannot hold
// the header or the ranges its count claims: the count is the writer's word, never copied beyond.
std::optional<VrsFrame> decodeVrs(const void* slot, size_t size, std::string* why);

// The pose now, as REP-105 has it: polylocd's map_T_odom (from its last update) after the base's
// newest odometry (`odom` null: polylocd's pose itself). polylocd updates every few centimetres of
// motion; odometry fills in between, which lets the robot stop within millimetres of its goal.
Eigen::Vector3d poseNow(const polyloc_pose& p, const polyloc_odometry* odom);

// Seconds from stamp t0_ns to t_ns, computed without integer overflow (the stamps are the
// writer's word: two far apart must not wrap the controller's clock).
double secondsBetween(int64_t t0_ns, int64_t t_ns);

// The stamp of polynav's last stop: just after the last command's (`last_ns`), so that the base
// takes it as the newest; `now_ns` when no command went out. Saturates instead of wrapping (at
// INT64_MAX, which polylocd never stamps, the base would refuse it as not newer).
int64_t stopStamp(int64_t last_ns, int64_t now_ns);

struct PoseRead {
  Eigen::Vector3d pose{0, 0, 0};  // x, y, yaw (map)
  bool localised = false;         // polylocd's pose was read and its status is tracking
};

// polylocd's pose now (odometry from channel `odom_ch` when >= 0 and readable). A failed read
// gives the identity pose, not localised: never uninitialised memory.
PoseRead readPoseNow(polyloc_client* c, int odom_ch);

}  // namespace polynav
