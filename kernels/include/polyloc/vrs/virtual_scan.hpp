// Virtual range scans (the thesis's VRS): every range sensor of the rig, at any mount, plus cone
// sensors, projected onto the floor plane into one 2D polar scan around base_link, so that any
// 2D obstacle avoidance sees table tops, chair seats and low boxes. Each segment holds the
// nearest obstacle between floor_clearance and robot_height, from
//   - direct sources: the latest frame of each (horizontal scanners, lidar);
//   - the obstacle memory (obstacle_memory.hpp), fed by memory sources (tilted scanners, ToF)
//     through the thesis's filters and read back by Bresenham up to its max_distance;
//   - danger zones (danger_zones.hpp), permanent virtual obstacles.
// A second scan, ranges_max, is the variant for localisation: per segment the farthest direct
// return (walls rather than the chair legs in front of them), no memory, no danger zones.
//
//   VirtualRangeScanner vrs(rig, robot, config.vrs, &map);
//   vrs.addFrame(sensor, stamp, map_T_base_at_stamp, ranges);   // any order, any rate
//   vrs.setMovingObjects(tracks);                                  // people: kept out of memory
//   VirtualScan s = vrs.update(stamp, map_T_base);                 // at the rate you need
#pragma once

#include <polyloc/config/robot.hpp>
#include <polyloc/geometry/pose.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/sensors/rig.hpp>
#include <polyloc/vrs/config.hpp>
#include <polyloc/vrs/danger_zones.hpp>
#include <polyloc/vrs/obstacle_memory.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace polyloc {

// What made a segment's range (bits: a segment may be equally near from two kinds).
enum VrsSourceBits : uint8_t { kVrsNone = 0, kVrsDirect = 1, kVrsMemory = 2, kVrsDanger = 4 };

// LaserScan-like (sensor_msgs/LaserScan with frame base_link): ranges[i] covers
// [angle_min + i increment, angle_min + (i + 1) increment); its ray is at the segment's centre.
struct VirtualScan {
  int64_t stamp_ns = 0;
  Pose map_T_base;
  float angle_min = 0, angle_increment = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges;       // nearest obstacle; +inf: none within range_max (REP-117)
  std::vector<uint8_t> source;     // VrsSourceBits per segment
  std::vector<float> ranges_max;   // localisation variant: farthest direct return, +inf none
  size_t size() const { return ranges.size(); }
  float angleOf(size_t i) const { return angle_min + (float(i) + 0.5f) * angle_increment; }
};

// A tracked moving object (tracking/): map-frame position at stamp_ns, velocity and the 2x2
// position covariance. Frames of other stamps test against the position moved by the velocity.
struct MovingObject {
  Eigen::Vector2d position{0, 0};
  Eigen::Vector2d velocity{0, 0};
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity() * 0.01;
  int64_t stamp_ns = 0;
};

struct VrsCounters {
  uint64_t frames = 0, frames_rejected = 0;  // rejected: unknown sensor, wrong size, pose not finite
  uint64_t updates = 0;
  uint64_t memory_inserted = 0;
  uint64_t memory_far = 0, memory_behind = 0, memory_moving = 0;  // points the memory filters kept out
};

class VirtualRangeScanner {
 public:
  // map: for danger-zone labels (may be null). Throws std::invalid_argument for a config that
  // names a sensor the rig does not have, or bad angles/resolution.
  VirtualRangeScanner(const Rig& rig, const RobotSpec& robot, const VrsConfig& config, const Mesh* map = nullptr);

  // One frame of rig sensor `sensor`: ranges along its beams (BeamSet order, as the localiser
  // takes them; NaN/inf/out of range are no return). map_T_base: the robot at the frame's stamp.
  // False (and counted) for an unknown sensor, a wrong size or a pose that is not finite.
  bool addFrame(size_t sensor, int64_t stamp_ns, const Pose& map_T_base, std::span<const float> ranges);
  // Points of rig sensor `sensor` already in base_link at the stamp (filtered ToF depth, lidar).
  bool addPoints(size_t sensor, int64_t stamp_ns, const Pose& map_T_base, std::span<const Eigen::Vector3f> base_points);
  // One reading of config cone `cone` (index into VrsConfig::cones).
  bool addCone(size_t cone, int64_t stamp_ns, const Pose& map_T_base, float range);
  // Tracked moving objects for the memory filter (the tracker's confirmed tracks, each call the
  // set at one stamp). Sets of the last memory.delay + 1 s are kept; an empty set, or objects
  // without stamps, replace them all.
  void setMovingObjects(std::span<const MovingObject> objects);

  VirtualScan update(int64_t stamp_ns, const Pose& map_T_base);

  const ObstacleMemory& memory() const { return memory_; }
  const DangerZones& dangerZones() const { return danger_; }
  const VrsCounters& counters() const { return counters_; }
  const VrsConfig& config() const { return config_; }
  // Mode each rig sensor got (VrsConfig::sources, or the default for its kind and mount).
  VrsMode modeOf(size_t sensor) const { return modes_[sensor]; }

 private:
  struct Frame {
    int64_t stamp = 0;
    std::vector<Eigen::Vector3f> points;  // map frame
    VrsMode mode = VrsMode::Off;
    bool fresh = false;  // not yet offered to the memory
    std::vector<int32_t> seg;   // per point at the last update: segment, -1 not in the scan
    std::vector<float> range;   // and its planar range
  };
  bool inBody(float x, float y) const;
  bool nearMoving(const Eigen::Vector2f& p, int64_t stamp) const;
  void store(Frame& f, int64_t stamp, const Pose& map_T_base, const Pose& base_T_source, std::span<const Eigen::Vector3f> pts);

  VrsConfig config_;
  Rig rig_;
  std::vector<BeamSet> beams_;
  std::vector<VrsMode> modes_;
  std::vector<Eigen::Vector2f> body_;  // footprint grown by self_margin (base frame)
  float body_radius_ = 0;              // round robots
  std::vector<Frame> frames_;          // per rig sensor, then per cone
  struct Pending {
    Eigen::Vector2f point;
    int64_t stamp;
  };
  std::vector<Pending> pending_;  // memory candidates waiting for memory.delay
  std::vector<MovingObject> moving_;
  std::vector<Eigen::Matrix2d> moving_info_;  // inverse covariances
  ObstacleMemory memory_;
  DangerZones danger_;
  VrsCounters counters_;
  size_t segments_ = 0;
  int64_t last_update_ = 0;
  Pose last_pose_;
  bool updated_ = false;
  // Per segment, reused: nearest direct return, nearest of the direct-only sources (the memory
  // filter's reference), farthest direct return.
  std::vector<float> direct_, plain_, far_;
};

}  // namespace polyloc
