// Motion detection for one level planar scanner: each scan's endpoints are compared with the
// free space of a few earlier scans of it (MotionConfig::reference_ages), ego-motion removed
// through the sensor's pose per scan (map_T_sensor from localisation, or odom_T_sensor from
// odometry). An endpoint has moved (a seed) when
//
// - appeared: an earlier scan saw free space there, with the margin band: every beam in a small
//   angular window around the bearing passed it by margin + margin_per_m * range; and no older
//   scan saw something there (a surface that comes and goes is grazed by the scan plane as the
//   robot rolls). A point an earlier scan could not see (behind something, out of view, an
//   invalid beam) is not motion: that is the laser shadow a moving robot looks into;
// - or receded: an object walking straight away stays in its own shadow, so a point also counts
//   when the beam now passes where an earlier scan's endpoint was (vacated), ends at most
//   max_speed * age (and recede_max) behind it, where that scan was blind because of what it saw
//   in front, and no scan as old saw the point;
//
// and StaticMemory does not know the place as static. Endpoints near a seed that are not static
// and were not there in the oldest reference join it (the other leg of a person).
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/planar_scanner.hpp>
#include <polyloc/tracking/config.hpp>
#include <polyloc/tracking/detections.hpp>
#include <polyloc/tracking/static_memory.hpp>

#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <vector>

namespace polyloc {

// A StaticMemory with the settings of c (static_cell, static_time, static_gap).
std::shared_ptr<StaticMemory> sharedStaticMemory(const MotionConfig& c);

enum class ScanCheck { Ok, WrongSize, BadPose, OutOfOrder };
const char* scanCheckName(ScanCheck c);

struct MotionCounters {
  uint64_t scans = 0;           // accepted
  uint64_t rejected = 0;        // wrong size, pose not finite, stamp not after the last
  uint64_t invalid_ranges = 0;  // NaN, negative, below range_min (counted, treated as unknown)
  uint64_t moved_points = 0;
  uint64_t pose_jumps = 0;      // scans dropped by max_moved_fraction
};

class MotionDetector {
 public:
  // Throws std::invalid_argument for settings that cannot work (no reference ages, negative margins).
  // Scanners of one robot share a StaticMemory (what one has seen for long is static for all);
  // without one the detector makes its own.
  MotionDetector(const PlanarScannerSpec& spec, const MotionConfig& config,
                 std::shared_ptr<StaticMemory> memory = nullptr);

  // Appends the moved endpoints of this scan to `out` (xy of the pose's parent frame) and keeps
  // the scan as a reference. `ranges`: one per beam, NaN invalid, +inf nothing within range_max.
  // A scan that is not Ok changes nothing.
  ScanCheck detect(int64_t stamp_ns, const Pose& map_T_sensor, std::span<const float> ranges,
                   std::vector<MotionPoint>& out);
  void reset() { history_.clear(), static_->clear(); }

  // What the latest scan saw of the disc of `radius` around p: Empty (every beam across it went
  // on beyond it), Occupied (a beam ended in it), Hidden (behind something, out of view or range).
  enum class Look { Empty, Occupied, Hidden };
  Look look(const Eigen::Vector2d& p, double radius) const;
  const MotionCounters& counters() const { return counters_; }

 private:
  struct Scan {
    int64_t stamp_ns = 0;
    Pose map_T_sensor, sensor_T_map;
    std::vector<float> free;             // per beam: free space along it (m), NaN unknown
    std::vector<Eigen::Vector3d> ends;   // per beam: endpoint in the parent frame, NaN if none usable
  };
  enum class Seen { Free, Hit, Occluded, Unknown };
  // margin < 0: the configured margin band at p's range. extra_rad widens the angular window.
  Seen classify(const Scan& s, const Eigen::Vector3d& p, int* beam, double* dist, double margin = -1,
                double extra_rad = 0) const;
  std::vector<const Scan*> references(int64_t stamp_ns) const;  // oldest first
  struct Marks {
    std::vector<char> moved;           // per beam of the scan: a seed
    std::vector<int64_t> seen_since;   // stamp of the oldest reference that saw the point there
    size_t compared = 0;               // endpoints compared
  };
  Scan makeScan(int64_t stamp_ns, const Pose& map_T_sensor, std::span<const float> ranges);
  Marks appeared(const Scan& cur, const std::vector<const Scan*>& refs) const;
  void receded(const Scan& cur, const std::vector<const Scan*>& refs, Marks& m) const;
  void grow(const Scan& cur, const std::vector<const Scan*>& refs, const Marks& m, std::vector<MotionPoint>& out) const;

  PlanarScannerSpec spec_;
  MotionConfig c_;
  size_t beams_ = 0;
  double angle_min_ = 0;
  std::vector<double> cos_, sin_;
  std::deque<Scan> history_;
  std::shared_ptr<StaticMemory> static_;
  MotionCounters counters_;
};

}  // namespace polyloc
