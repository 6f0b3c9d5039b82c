// A recorded real run with known poses, as the real-log evaluation takes it (`polyloc eval
// carmen`, docs/localization.md "Real logs"): the laser scans of one topic, each with the pose
// the log gives for it (a corrected CARMEN log: the SLAM result, i.e. ground truth), and the
// log's own odometry, all in file order. The CARMEN reader publishes each scan's logged pose on
// `<topic>_pose` right after the scan (docs/recordings.md); a scan without one is counted.
//
//   RealLog log = readRealLog("../shared/data/carmen/aces-corrected.log.gz");
//   log.scans[i].scan.ranges, log.scans[i].pose, log.odometry[k]
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/messages.hpp>
#include <polyloc/io/recording.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

struct LoggedScan {
  int64_t stamp_ns = 0;  // as recorded (may be 0, repeated or going backwards in old logs)
  uint64_t order = 0;    // index of the message in the log (file order)
  msg::LaserScan scan;
  Pose pose;             // the laser's logged pose in the world (z = 0)
};

struct LoggedOdometry {
  int64_t stamp_ns = 0;
  uint64_t order = 0;
  Pose pose;             // odom_T_base
};

struct RealLog {
  std::string path, topic;
  std::vector<LoggedScan> scans;         // of `topic`, in file order, each with its pose
  std::vector<LoggedOdometry> odometry;  // /odom, in file order, stamps as recorded
  uint64_t messages = 0;                 // read from the log
  uint64_t scans_without_pose = 0;       // scans of `topic` not followed by their pose
  ReadStats stats;                       // the reader's
};

// Reads the whole log. topic: the scan topic ("" = the first LaserScan topic that has poses on
// `<topic>_pose`). Throws std::runtime_error naming the file when it has no scan with a pose.
RealLog readRealLog(const std::string& path, const std::string& topic = "");

}  // namespace polyloc
