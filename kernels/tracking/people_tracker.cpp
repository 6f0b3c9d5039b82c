#include <polyloc/tracking/people_tracker.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {

std::vector<size_t> trackingSensors(const Rig& rig, const TrackingConfig& config) {
  std::vector<size_t> out;
  if (config.sensors.empty()) {
    for (size_t i = 0; i < rig.size(); ++i)
      if (rig.isLevelScanner(i)) out.push_back(i);  // motion detection compares bearings in the scan plane
    if (out.empty()) throw std::invalid_argument("tracking: rig '" + rig.name + "' has no level planar scanner");
    return out;
  }
  for (const std::string& name : config.sensors) {
    const int i = rig.find(name);
    if (i < 0) throw std::invalid_argument("tracking: sensor '" + name + "' is not in rig '" + rig.name + "'");
    const Sensor& s = rig.sensors[size_t(i)];
    if (!std::holds_alternative<PlanarScannerSpec>(s.spec))
      throw std::invalid_argument("tracking: sensor '" + name + "' is a " + s.typeName() + ", not a planar scanner");
    if (!rig.isLevelScanner(size_t(i))) throw std::invalid_argument("tracking: sensor '" + name + "' is tilted more than 10 deg");
    if (std::find(out.begin(), out.end(), size_t(i)) == out.end()) out.push_back(size_t(i));
  }
  return out;
}

PeopleTracker::PeopleTracker(const Rig& rig, const TrackingConfig& config)
    : c_(config), sensors_(trackingSensors(rig, config)), detectors_(rig.size()), tracker_(config.tracker) {
  const std::shared_ptr<StaticMemory> memory = sharedStaticMemory(c_.motion);  // one robot, one memory
  for (size_t i : sensors_)
    detectors_[i] = std::make_unique<MotionDetector>(std::get<PlanarScannerSpec>(rig.sensors[i].spec), c_.motion, memory);
}

PeopleTracker::~PeopleTracker() = default;

ScanCheck PeopleTracker::addScan(size_t sensor, int64_t stamp_ns, const Pose& map_T_sensor,
                                 std::span<const float> ranges) {
  if (sensor >= detectors_.size() || !detectors_[sensor]) {
    ++counters_.ignored;
    return ScanCheck::Ok;
  }
  const int64_t tol = std::llround(c_.sync_tolerance * 1e9);
  if (pending_ns_ && stamp_ns > *pending_ns_ + tol) flush();
  // A scan older than the step already tracked cannot go in any more.
  if (counters_.steps > 0 && !pending_ns_ && stamp_ns < last_step_ns_) {
    ++counters_.rejected;
    return ScanCheck::OutOfOrder;
  }
  const ScanCheck check = detectors_[sensor]->detect(stamp_ns, map_T_sensor, ranges, pending_);
  if (check != ScanCheck::Ok) {
    ++counters_.rejected;
    return check;
  }
  ++counters_.scans;
  if (!pending_ns_) pending_ns_ = stamp_ns;
  step_sensors_.push_back(sensor);
  return check;
}

void PeopleTracker::flush() {
  if (!pending_ns_) return;
  const int64_t stamp = *pending_ns_;
  detections_ = clusterDetections(pending_, c_.cluster, stamp);
  pending_.clear();
  pending_ns_.reset();
  // What the scanners of this step saw at a track's place: occupied by any, else empty by any.
  auto seen = [&](const Eigen::Vector2d& p) {
    bool empty = false;
    for (size_t i : step_sensors_) {
      const MotionDetector::Look l = detectors_[i]->look(p, c_.tracker.empty_radius);
      if (l == MotionDetector::Look::Occupied) return Visibility::Occupied;
      empty = empty || l == MotionDetector::Look::Empty;
    }
    return empty ? Visibility::Empty : Visibility::Hidden;
  };
  const bool updated = tracker_.update(stamp, detections_, seen);
  step_sensors_.clear();
  if (updated) {
    ++counters_.steps;
    counters_.detections += detections_.size();
    last_step_ns_ = stamp;
  }
}

}  // namespace polyloc
