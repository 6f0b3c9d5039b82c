// Settings of the virtual range scan (the `vrs:` section; docs/vrs.md has every key). Angles in
// radians here, degrees in YAML.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace polyloc {

// How the frames of one rig sensor reach the VRS.
enum class VrsMode {
  Direct,  // its latest frame goes into the scan as it is
  Memory,  // its points go through the obstacle memory (tilted scanners, ToF: they see briefly)
  Both,    // direct and into memory
  Off,     // not used
};

struct VrsSource {
  std::string sensor;           // rig sensor name
  VrsMode mode = VrsMode::Direct;
};

// A cone sensor (sonar, IR): the cone filled with points at the measured range, as the thesis
// models them. Not part of the rig (the simulator has no such sensors); mounts in base_link.
struct VrsCone {
  std::string name;
  Eigen::Vector3d position{0, 0, 0};  // base_link
  double yaw = 0, pitch = 0;          // axis direction (rad; pitch > 0 tilts down, REP-103)
  double half_angle = 0.26;           // rad (15 deg)
  double range_min = 0.05, range_max = 3.0;
  VrsMode mode = VrsMode::Direct;
};

struct ObstacleMemoryConfig {
  bool enabled = true;
  double resolution = 0.05;       // m per cell
  int cells = 512;                // the grid is cells x cells, wrapping around (25.6 m at 5 cm)
  double max_distance = 3.0;      // m: points farther from the robot do not enter; read-back range
  // A point enters only if nearer than the direct sources' range in its segment by this much:
  // a wall both see is not remembered because of range noise.
  double direct_margin = 0.05;    // m
  double lifetime = 10.0;         // s of motion: a cell not seen again for this long is forgotten
  // Aging runs only while the robot moves or turns faster than this (a table edge must not
  // walk away while the robot stands in front of it).
  double moving_speed = 0.02;     // m/s
  double moving_turn_rate = 0.035;  // rad/s (2 deg/s)
  // Tracked moving objects: points within this Mahalanobis distance of a track, or closer than
  // track_radius to its centre (a person's body is larger than the track's uncertainty), stay out.
  // Points wait this long before they enter, and are then tested against the tracks as they are
  // by then (moved back to the point's stamp): a person is seen before a track confirms them.
  double delay = 1.0;             // s
  double track_sigmas = 3.0;
  double track_radius = 0.5;      // m: half a body with swinging arms, plus the lag of a frame
};

struct VrsConfig {
  double angle_min = -M_PI;       // base_link, first segment's lower edge
  double angle_max = M_PI;
  double resolution = M_PI / 360;  // segment width (0.5 deg)
  size_t segments() const { return size_t(std::ceil((angle_max - angle_min) / resolution - 1e-9)); }
  double range_max = 8.0;         // m; segments with nothing nearer are +inf (REP-117)
  double floor_clearance = 0.06;  // m above base_link: lower points are floor
  // A beam pointing down that ends within this fraction of the range where it meets the floor
  // plane is floor too: range noise of a tilted scanner lifts floor points above any fixed
  // clearance (URG-04LX: 3% of 1.5 m is 3 cm in height at 40 deg).
  double floor_range_margin = 0.08;
  double robot_height = 1.2;      // m: higher points cannot touch the robot (robot.height)
  double self_margin = 0.02;      // m: points inside the footprint grown by this are the robot
  double max_age = 0.5;           // s: a direct source's frame older than this at update is dropped
  std::vector<VrsSource> sources; // empty: planar scanners and lidars direct, the rest memory
  std::vector<VrsCone> cones;
  ObstacleMemoryConfig memory;
  // Danger zones: map triangles with these labels (their floor projection) and polygons given
  // here (map frame) are permanent virtual obstacles.
  std::vector<std::string> danger_labels{"danger"};
  std::vector<std::vector<Eigen::Vector2d>> danger_zones;
  double danger_resolution = 0.05;  // m, raster of the zones
};

}  // namespace polyloc

