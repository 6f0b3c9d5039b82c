// Which rig sensor a recorded topic feeds (`polyloc localize`, docs/localization.md): the
// simulator's /scan/<sensor> (LaserScan) and /depth/<sensor>/image (32FC1 depth in m or 16UC1 in
// mm), a depth Image elsewhere on the sensor its namespace names (/camera/depth/image_raw:
// camera_depth), a LaserScan on /<sensor>, and CARMEN's /front_laser, /rear_laser, /robot_laser on the first, second, first
// planar scanner of the rig when no sensor has that name; /ground_truth/... topics are no sensor.
// Turns a message into the ranges the
// Localizer takes, or says why it cannot (counted by the caller, warned once per topic).
#pragma once

#include <polyloc/io/messages.hpp>
#include <polyloc/sensors/rig.hpp>

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace polyloc::reloc {

class TopicRouter {
 public:
  // enabled: per rig sensor, whether its frames go to the filter (--sensors).
  TopicRouter(const Rig& rig, std::vector<bool> enabled);

  // WrongSize: a scan's count (or an image's size) differs from the sensor's; WrongGeometry: the
  // count agrees but the recorded angles do not (io/recorded_geometry.hpp).
  enum class Kind { Frame, Ignored, UnknownSensor, Disabled, WrongSize, WrongGeometry, BadImage };
  struct Result {
    Kind kind = Kind::Ignored;
    int sensor = -1;
    int64_t stamp_ns = 0;     // header stamp (the log time when the header has none)
    std::string why;          // for warnings
  };
  // For a LaserScan or a depth Image: fills `ranges` (the sensor's beam order) on Kind::Frame.
  Result route(const std::string& topic, int64_t log_time_ns, const msg::Message& m, std::vector<float>& ranges);
  // The rig sensor a LaserScan topic feeds, or -1.
  int sensorForScan(const std::string& topic) const;

 private:
  int sensorForDepth(const std::string& topic) const;

  const Rig& rig_;
  std::vector<bool> enabled_;
  std::vector<size_t> beams_;                       // per sensor: expected number of ranges
  std::vector<std::vector<float>> depth_factor_;    // per depth camera: depth -> range
  std::vector<int> planar_;                         // planar scanners, in rig order
  mutable std::unordered_map<std::string, int> scan_cache_, depth_cache_;
};

}  // namespace polyloc::reloc
