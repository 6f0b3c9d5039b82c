// What the live view sends, encoded (docs/live.md lists the channels): ROS 2 messages as CDR
// with their ros2msg schemas, the map as a foxglove.SceneUpdate and polyloc's own views as JSON.
// Pure functions of their inputs, so tests decode exactly what a client gets.
#pragma once

#include "live/foxglove_server.hpp"

#include <polyloc_shm.h>

#include <polyloc/depth/frame.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/sensors/rig.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace polyloc::live {

using Bytes = std::vector<uint8_t>;

// A channel of a ROS 2 type ("sensor_msgs/msg/LaserScan") in CDR, with its ros2msg schema.
ChannelSpec cdrChannel(const std::string& topic, const std::string& type, bool latched = false);
// A JSON channel: foxglove.SceneUpdate or polyloc's own (polyloc.TopView, polyloc.MapSlice, polyloc.Health).
ChannelSpec jsonChannel(const std::string& topic, const std::string& schema_name, bool latched = false);

// The whole mesh as one entity of triangle lists, one list per label class, coloured as the PNGs.
Bytes sceneOfMesh(const Mesh& map);
// The map cut at `height` above z = 0, as line segments with labels (the page draws them).
Bytes mapSliceJson(const Mesh& map, float height);

Bytes poseCdr(const MclEstimate& e);  // geometry_msgs/PoseWithCovarianceStamped, frame map
Bytes groundTruthCdr(int64_t stamp_ns, const Pose& map_T_base);  // geometry_msgs/PoseStamped, frame map
// sensor_msgs/PointCloud2 in map: x y z yaw weight (float32), every k-th particle so that at
// most `max_points` go out; weight normalised to the largest of the set.
Bytes particlesCdr(int64_t stamp_ns, const ParticleSet& p, size_t max_points);
// Every k-th of n particles so that at most max_points remain (the cloud and the top view).
size_t particleStride(size_t n, size_t max_points);
// /tf: map -> odom (the correction) and odom -> base_link.
Bytes tfCdr(int64_t stamp_ns, const Pose& map_T_odom, const Pose& odom_T_base);
// /tf_static: base_link -> every sensor of the rig (the frames scans and clouds are in).
Bytes tfStaticCdr(const Rig& rig);

struct ScanShape {
  float angle_min = 0, angle_increment = 0, range_min = 0, range_max = 0;
};
Bytes laserScanCdr(int64_t stamp_ns, const std::string& frame, const ScanShape& shape, std::span<const float> ranges);
Bytes vrsCdr(const VirtualScan& v);                // LaserScan in base_link
Bytes tracksCdr(const polyloc_tracks& t);          // polyloc_msgs/TrackArray in map
Bytes depthCdr(int64_t stamp_ns, const DepthFilterResult& d);  // PointCloud2 x y z in base_link
// A lidar's frame as PointCloud2 x y z in the sensor's frame: the returns within its range.
Bytes rangesCloudCdr(int64_t stamp_ns, const std::string& frame, const BeamSet& beams, std::span<const float> ranges);

// polyloc.TopView: what the page draws, in map coordinates (see page.html).
struct TopView {
  int64_t stamp_ns = 0;
  bool have_pose = false;
  MclEstimate pose;
  std::vector<float> particles;  // x, y, yaw
  std::vector<float> vrs;        // x, y of the VRS obstacles
  std::vector<polyloc_track> tracks;
  std::string status;
};
Bytes topViewJson(const TopView& v);
// polyloc.Health: polylocd's health frame, its inputs by name, and the viewers' counters.
Bytes healthJson(const polyloc_health& h, const std::vector<std::string>& inputs, const ServerStats& viewers);

}  // namespace polyloc::live
