// A round of sensor updates: after enough motion every weighed sensor contributes its next frame,
// and only then is the round closed (resampling, estimate). Which sensors are still awaited, the
// round's frames kept for the refinement, and its tallies.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/refine.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace polyloc {

class UpdateRound {
 public:
  UpdateRound() = default;
  // `weighed`: per rig sensor, 1 when its frames are weighed (the others are never awaited).
  UpdateRound(const MclConfig& config, std::vector<uint8_t> weighed);

  // A frame older than the last one of its sensor is stale; heard() records the last one.
  bool stale(size_t sensor, int64_t stamp) const { return stamp < last_scan_[sensor]; }
  void heard(size_t sensor, int64_t stamp) { last_scan_[sensor] = stamp; }

  bool open() const;                   // some sensor is still awaited
  bool timedOut(int64_t stamp) const;  // open for longer than round_timeout
  // Whether a round starts now, `moved` (base) since the last round started.
  bool due(const Pose& moved) const;
  void start(size_t sensor, int64_t stamp);
  // True when `sensor` was awaited, which it no longer is: its frame is weighed.
  bool take(size_t sensor);
  bool complete() const;  // no sensor awaited any more
  void abandon();         // awaits no sensor any more (closed on timeout)
  // The filter was re-initialised: no round open, the next frame starts one. The kept frames
  // stay flagged until the round closes.
  void reset();

  void keep(size_t sensor, std::span<const float> ranges, const Pose& odom);
  // The round's kept frames, as refinePose takes them: relative to odometry `ref` (the particles'
  // time: the odometry of the last weighed frame).
  std::vector<RefineScan> scans(const Pose& ref) const;
  void clear();  // the round closed: tallies zero, frames no longer kept

  // The open round: sensors weighed, of them lost, collapsed weightings, largest injection due,
  // stamp of the last frame weighed.
  size_t sensors = 0, lost = 0, collapsed = 0;
  double inject_due = 0;
  int64_t stamp = 0;

 private:
  struct RoundFrame {
    std::vector<float> ranges;
    Pose odom;
    bool valid = false;
  };
  double round_timeout_ = 0, update_min_distance_ = 0, update_min_angle_ = 0;
  std::vector<uint8_t> weighed_;
  std::vector<uint8_t> pending_;
  std::vector<int64_t> last_scan_;
  std::vector<RoundFrame> frames_;  // per rig sensor: its frame of the open round (refine)
  int64_t start_ = 0;
  bool started_once_ = false;
};

}  // namespace polyloc
