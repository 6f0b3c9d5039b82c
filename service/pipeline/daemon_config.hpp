// polylocd's own settings: the `polylocd:` section of the polyloc config file (the rest of the
// file is PolylocConfig: map, robot, rig, mcl, vrs, tracking, depth_filter). Every key has a
// default; docs/polylocd.md lists them.
//
//   polylocd:
//     instance: lab          # shared-memory segment /polyloc.lab
//     threads: 0             # TBB arena for the kernels (0: all cores)
//     slots: 16              # ring slots per channel
//     clock: wall            # wall: stamps are CLOCK_REALTIME; source: time is the newest input stamp
//     max_age: 0.5           # s: older frames are stale
//     max_future: 0.1        # s: frames stamped later than now + this are rejected (source: 2 s)
//     clock_agree: 5         # source: refused frames in a row that move the clock (a jump)
//     input_timeout: 1.0     # s: an input silent this long is reported (health, log)
//     odom_wait: 0.05        # s a sensor frame waits for the odometry covering its stamp (0: none)
//     global_search: beside  # beside: on a thread of its own; inline: in the input thread
//     health_rate: 10        # Hz
//     init: global           # global | ground_truth-free start pose {x, y, z, yaw, sigma_xy, sigma_yaw}
//     control: {enabled: true, bind: 127.0.0.1, port: 7410}
//     live: {port: 8765, address: 127.0.0.1}   # the live view (docs/live.md); port 0: off
//     log_level: info
#pragma once

#include "live/live_view.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/geometry/pose.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace polyloc::pipeline {

struct InitPose {
  Pose pose;
  double sigma_xy = 0.1, sigma_yaw = 0.0873;  // m, rad
};

struct ControlConfig {
  bool enabled = true;
  std::string bind = "127.0.0.1";  // loopback: the control endpoint is for the robot's own computer
  uint16_t port = 7410;
};

struct DaemonConfig {
  std::string instance = "polyloc";
  int threads = 0;
  uint32_t slots = 16;
  bool source_clock = false;
  int64_t max_age_ns = 500'000'000;
  int64_t max_future_ns = 100'000'000;  // 2 s under clock: source when not set
  size_t clock_agree = 5;
  int64_t input_timeout_ns = 1'000'000'000;
  int64_t odom_wait_ns = 50'000'000;  // then the motion is extrapolated, and counted (extrapolated)
  // A global search on a thread of its own, so that VRS, tracks and health keep their rate while
  // it works (pipeline.hpp); false: inline, every output waits for it (byte-identical VRS and
  // tracks under any timing).
  bool search_beside = true;
  double health_rate_hz = 10;
  std::optional<InitPose> init;  // nullopt: global localisation
  ControlConfig control;
  live::LiveConfig live;
  std::string log_level = "info";
};

struct ServiceConfig {
  PolylocConfig polyloc;
  DaemonConfig daemon;
};

// Reads the whole file; errors are ConfigError naming file, line and key.
ServiceConfig loadServiceConfig(const std::string& path);
DaemonConfig parseDaemonConfig(ConfigMap m);

}  // namespace polyloc::pipeline
