// The tracking pipeline: a MotionDetector per level planar scanner of the rig, the moved points of
// scans taken together (within sync_tolerance) clustered into one set of detections, and the
// MultiTargetTracker fed with them. Poses are given per scan (map_T_sensor: localisation, or
// odom_T_sensor: odometry; the tracks are in that frame). No threads, no I/O.
//
//   PeopleTracker people(rig, config.tracking);
//   people.addScan(sensor, stamp_ns, map_T_base * rig.sensors[sensor].mount, ranges);
//   ...
//   people.flush();                       // or: the next scan's stamp closes the step
//   for (const TrackState& t : people.tracks().items) ...
#pragma once

#include <polyloc/sensors/rig.hpp>
#include <polyloc/tracking/config.hpp>
#include <polyloc/tracking/motion_detector.hpp>
#include <polyloc/tracking/tracker.hpp>

#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace polyloc {

struct TrackingCounters {
  uint64_t scans = 0;             // accepted scans of tracking scanners
  uint64_t rejected = 0;          // wrong size, pose not finite, out of order (see MotionDetector)
  uint64_t ignored = 0;           // scans of sensors tracking does not use
  uint64_t steps = 0;             // tracker updates
  uint64_t detections = 0;
};

class PeopleTracker {
 public:
  // Throws std::invalid_argument when a named sensor is not in the rig, is not a planar scanner
  // or is not level (scan plane more than 10 deg from horizontal), or when no scanner is left.
  PeopleTracker(const Rig& rig, const TrackingConfig& config);
  ~PeopleTracker();

  // One scan of rig sensor `sensor`. Returns what became of it (Ok also for ignored sensors).
  // A scan later than the pending step by more than sync_tolerance first closes that step.
  ScanCheck addScan(size_t sensor, int64_t stamp_ns, const Pose& map_T_sensor, std::span<const float> ranges);
  // Clusters the pending scans' moved points and updates the tracks now.
  void flush();

  const Tracks& tracks() const { return tracker_.tracks(); }
  const MultiTargetTracker& tracker() const { return tracker_; }
  const std::vector<Detection>& detections() const { return detections_; }  // of the last step
  const std::vector<size_t>& sensors() const { return sensors_; }             // rig indices used
  const TrackingCounters& counters() const { return counters_; }

 private:
  TrackingConfig c_;
  std::vector<size_t> sensors_;
  std::vector<std::unique_ptr<MotionDetector>> detectors_;  // per rig sensor; null: not used
  MultiTargetTracker tracker_;
  std::vector<MotionPoint> pending_;
  std::vector<size_t> step_sensors_;   // scanners that delivered to the open step
  std::optional<int64_t> pending_ns_;  // stamp of the first scan of the open step
  int64_t last_step_ns_ = 0;
  std::vector<Detection> detections_;
  TrackingCounters counters_;
};

// Rig indices of the scanners a config uses (the rules of the constructor above).
std::vector<size_t> trackingSensors(const Rig& rig, const TrackingConfig& config);

}  // namespace polyloc
