// The ROS 2 messages polyloc records and reads, as plain structs that mirror the .msg
// definitions field by field (sensor_msgs, nav_msgs, tf2_msgs, geometry_msgs), so the CDR codec
// is a straight walk over the fields. Only what polyloc uses is here.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace polyloc::msg {

struct Time {  // builtin_interfaces/Time
  int32_t sec = 0;
  uint32_t nanosec = 0;
};
inline int64_t toNs(const Time& t) { return int64_t{t.sec} * 1000000000 + t.nanosec; }
inline Time fromNs(int64_t ns) {
  int64_t s = ns / 1000000000, r = ns % 1000000000;
  if (r < 0) --s, r += 1000000000;
  return {static_cast<int32_t>(s), static_cast<uint32_t>(r)};
}

struct Header {  // std_msgs/Header
  Time stamp;
  std::string frame_id;
};

struct Vector3 { double x = 0, y = 0, z = 0; };
struct Point { double x = 0, y = 0, z = 0; };
struct Quaternion { double x = 0, y = 0, z = 0, w = 1; };
struct Pose { Point position; Quaternion orientation; };             // geometry_msgs/Pose
struct PoseStamped { Header header; Pose pose; };
struct PoseWithCovariance { Pose pose; std::array<double, 36> covariance{}; };
struct PoseWithCovarianceStamped { Header header; PoseWithCovariance pose; };  // AMCL's /amcl_pose
struct Twist { Vector3 linear, angular; };
struct TwistWithCovariance { Twist twist; std::array<double, 36> covariance{}; };
struct Transform { Vector3 translation; Quaternion rotation; };
struct TransformStamped { Header header; std::string child_frame_id; Transform transform; };

struct LaserScan {  // sensor_msgs/LaserScan
  Header header;
  float angle_min = 0, angle_max = 0, angle_increment = 0;
  float time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
};

struct PointField {  // sensor_msgs/PointField
  enum : uint8_t { INT8 = 1, UINT8, INT16, UINT16, INT32, UINT32, FLOAT32, FLOAT64 };
  std::string name;
  uint32_t offset = 0;
  uint8_t datatype = FLOAT32;
  uint32_t count = 1;
};

struct PointCloud2 {
  Header header;
  uint32_t height = 1, width = 0;
  std::vector<PointField> fields;
  bool is_bigendian = false;
  uint32_t point_step = 0, row_step = 0;
  std::vector<uint8_t> data;
  bool is_dense = true;
};

struct Image {  // depth as "32FC1" (metres), amplitude as "32FC1" or "16UC1"
  Header header;
  uint32_t height = 0, width = 0;
  std::string encoding;
  uint8_t is_bigendian = 0;
  uint32_t step = 0;
  std::vector<uint8_t> data;
};

struct RegionOfInterest {
  uint32_t x_offset = 0, y_offset = 0, height = 0, width = 0;
  bool do_rectify = false;
};

struct CameraInfo {
  Header header;
  uint32_t height = 0, width = 0;
  std::string distortion_model = "plumb_bob";
  std::vector<double> d;
  std::array<double, 9> k{}, r{};
  std::array<double, 12> p{};
  uint32_t binning_x = 0, binning_y = 0;
  RegionOfInterest roi;
};

struct Odometry {  // nav_msgs/Odometry
  Header header;
  std::string child_frame_id;
  PoseWithCovariance pose;
  TwistWithCovariance twist;
};

struct TFMessage {  // tf2_msgs/TFMessage
  std::vector<TransformStamped> transforms;
};

// polyloc_msgs/Track, TrackArray: tracked moving objects (people) in the header's frame, as
// polyloc perceive writes them and the simulator writes the true people (/ground_truth/people).
struct Track {
  uint32_t id = 0;
  uint8_t status = 0;                // 0 tentative, 1 confirmed, 2 deleted (truth: 1 visible, 0 not)
  double x = 0, y = 0, vx = 0, vy = 0;
  std::array<double, 4> covariance{};  // position, row-major 2x2
};
struct TrackArray {
  Header header;
  std::vector<Track> tracks;
};

using Message = std::variant<LaserScan, PointCloud2, Image, CameraInfo, Odometry, TFMessage, PoseStamped, TrackArray,
                             PoseWithCovarianceStamped>;

// ROS 2 type name of a message ("sensor_msgs/msg/LaserScan", ...).
const char* typeName(const Message& m);
// All supported type names, in variant order.
const std::vector<std::string>& supportedTypes();

}  // namespace polyloc::msg
