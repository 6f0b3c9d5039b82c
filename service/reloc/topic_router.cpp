#include "reloc/topic_router.hpp"
#include "reloc/recorded_rig.hpp"

#include <polyloc/io/depth_image.hpp>
#include <polyloc/io/recorded_geometry.hpp>

#include <fmt/core.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace polyloc::reloc {

TopicRouter::TopicRouter(const Rig& rig, std::vector<bool> enabled) : rig_(rig), enabled_(std::move(enabled)) {
  enabled_.resize(rig.size(), true);
  for (size_t i = 0; i < rig.size(); ++i) {
    const Sensor& s = rig.sensors[i];
    beams_.push_back(s.beams().size());
    const auto* cam = std::get_if<DepthCameraSpec>(&s.spec);
    depth_factor_.push_back(cam ? cam->depthFactors() : std::vector<float>{});
    if (std::holds_alternative<PlanarScannerSpec>(s.spec)) planar_.push_back(static_cast<int>(i));
  }
}

int TopicRouter::sensorForScan(const std::string& topic) const {
  if (auto it = scan_cache_.find(topic); it != scan_cache_.end()) return it->second;
  const std::string name = sensorNameForTopic(topic);
  int s = rig_.find(name);
  // CARMEN logs name their lasers, not the rig's sensors: front and robot laser -> the first
  // planar scanner, rear laser -> the second (docs/localization.md).
  if (s < 0 && (name == "front_laser" || name == "robot_laser") && !planar_.empty()) s = planar_[0];
  if (s < 0 && name == "rear_laser" && planar_.size() > 1) s = planar_[1];
  scan_cache_[topic] = s;
  return s;
}

int TopicRouter::sensorForDepth(const std::string& topic) const {
  if (auto it = depth_cache_.find(topic); it != depth_cache_.end()) return it->second;
  const int s = rig_.find(depthSensorNameForTopic(topic));
  depth_cache_[topic] = s;
  return s;
}

TopicRouter::Result TopicRouter::route(const std::string& topic, int64_t log_time_ns, const msg::Message& m,
                                       std::vector<float>& ranges) {
  Result r;
  // Ground truth the simulator records (/ground_truth/vrs is a LaserScan too) is no sensor.
  if (topic.rfind("/ground_truth", 0) == 0) return r;
  if (const auto* scan = std::get_if<msg::LaserScan>(&m)) {
    r.sensor = sensorForScan(topic);
    if (r.sensor < 0) {
      r.kind = Kind::UnknownSensor;
      r.why = fmt::format("{}: no sensor of rig '{}' for this scan topic", topic, rig_.name);
      return r;
    }
    r.stamp_ns = msg::toNs(scan->header.stamp);
    if (!enabled_[r.sensor]) return r.kind = Kind::Disabled, r;
    if (std::string mismatch = geometryMismatch(rig_.sensors[r.sensor], *scan); !mismatch.empty()) {
      r.kind = scan->ranges.size() != beams_[r.sensor] ? Kind::WrongSize : Kind::WrongGeometry;
      r.why = fmt::format("{}: {}", topic, mismatch);
      return r;
    }
    if (scan->ranges.size() != beams_[r.sensor]) {  // a lidar's organised cloud: its count only
      r.kind = Kind::WrongSize;
      r.why = fmt::format("{}: {} ranges, sensor '{}' has {} beams", topic, scan->ranges.size(),
                          rig_.sensors[r.sensor].name, beams_[r.sensor]);
      return r;
    }
    ranges.assign(scan->ranges.begin(), scan->ranges.end());
  } else if (const auto* img = std::get_if<msg::Image>(&m)) {
    r.sensor = sensorForDepth(topic);
    if (r.sensor < 0) return r;  // amplitude images, other cameras: not for the filter
    r.stamp_ns = msg::toNs(img->header.stamp);
    const auto& factor = depth_factor_[r.sensor];
    if (factor.empty()) {
      r.kind = Kind::UnknownSensor;
      r.why = fmt::format("{}: sensor '{}' is not a depth camera", topic, rig_.sensors[r.sensor].name);
      return r;
    }
    if (!enabled_[r.sensor]) return r.kind = Kind::Disabled, r;
    const size_t n = size_t(img->width) * img->height;
    if (n != factor.size()) {
      r.kind = Kind::WrongSize;
      r.why = fmt::format("{}: {}x{} image, sensor '{}' has {} pixels", topic, img->width, img->height,
                          rig_.sensors[r.sensor].name, factor.size());
      return r;
    }
    if (std::string bad = depthImageToMetres(*img, ranges); !bad.empty()) {
      r.kind = Kind::BadImage;
      r.why = fmt::format("{}: {} (sensor '{}')", topic, bad, rig_.sensors[r.sensor].name);
      return r;
    }
    // Depth cameras give depth along the optical axis; the filter wants range along the ray.
    for (size_t b = 0; b < n; ++b)
      ranges[b] = factor[b] > 0 ? ranges[b] / factor[b] : std::numeric_limits<float>::quiet_NaN();
  } else {
    return r;  // odometry, tf, point clouds, camera info: the caller's or nobody's
  }
  if (r.stamp_ns == 0) r.stamp_ns = log_time_ns;  // a header without a stamp
  r.kind = Kind::Frame;
  return r;
}

}  // namespace polyloc::reloc
