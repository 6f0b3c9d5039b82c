// The ros2msg definitions of the message types polyloc records, as ROS 2 Humble/Jazzy ship them
// (comments dropped; field order, types, array bounds, defaults and constants as in the .msg
// files). MCAP and rosbag2 carry them so that tools without the ROS packages (Foxglove, the MCAP
// CLI) can decode the CDR payloads.
#include <polyloc/io/cdr.hpp>

#include <map>
#include <set>
#include <utility>

namespace polyloc::msg {
namespace {

struct Definition {
  const char* text;                 // the .msg body
  std::vector<const char*> deps;    // "pkg/Type" of the complex fields, in field order
};

// Keyed by "pkg/Type", the form the "MSG:" separator lines use.
const std::map<std::string, Definition>& definitions() {
  static const std::map<std::string, Definition> defs = {
      {"builtin_interfaces/Time", {"int32 sec\nuint32 nanosec\n", {}}},
      {"std_msgs/Header",
       {"builtin_interfaces/Time stamp\nstring frame_id\n", {"builtin_interfaces/Time"}}},
      {"geometry_msgs/Vector3", {"float64 x\nfloat64 y\nfloat64 z\n", {}}},
      {"geometry_msgs/Point", {"float64 x\nfloat64 y\nfloat64 z\n", {}}},
      {"geometry_msgs/Quaternion", {"float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n", {}}},
      {"geometry_msgs/Pose",
       {"Point position\nQuaternion orientation\n",
        {"geometry_msgs/Point", "geometry_msgs/Quaternion"}}},
      {"geometry_msgs/PoseStamped",
       {"std_msgs/Header header\nPose pose\n", {"std_msgs/Header", "geometry_msgs/Pose"}}},
      {"geometry_msgs/PoseWithCovariance",
       {"Pose pose\nfloat64[36] covariance\n", {"geometry_msgs/Pose"}}},
      {"geometry_msgs/PoseWithCovarianceStamped",
       {"std_msgs/Header header\nPoseWithCovariance pose\n",
        {"std_msgs/Header", "geometry_msgs/PoseWithCovariance"}}},
      {"geometry_msgs/Twist",
       {"Vector3  linear\nVector3  angular\n", {"geometry_msgs/Vector3"}}},
      {"geometry_msgs/TwistWithCovariance",
       {"Twist twist\nfloat64[36] covariance\n", {"geometry_msgs/Twist"}}},
      {"geometry_msgs/Transform",
       {"Vector3 translation\nQuaternion rotation\n",
        {"geometry_msgs/Vector3", "geometry_msgs/Quaternion"}}},
      {"geometry_msgs/TransformStamped",
       {"std_msgs/Header header\nstring child_frame_id\nTransform transform\n",
        {"std_msgs/Header", "geometry_msgs/Transform"}}},
      // polyloc's own: tracked moving objects (docs/recordings.md).
      {"polyloc_msgs/Track",
       {"uint32 id\nuint8 status\nfloat64 x\nfloat64 y\nfloat64 vx\nfloat64 vy\nfloat64[4] covariance\n", {}}},
      {"polyloc_msgs/TrackArray",
       {"std_msgs/Header header\nTrack[] tracks\n", {"std_msgs/Header", "polyloc_msgs/Track"}}},
      {"sensor_msgs/LaserScan",
       {"std_msgs/Header header\n"
        "float32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
        "float32 time_increment\nfloat32 scan_time\n"
        "float32 range_min\nfloat32 range_max\n"
        "float32[] ranges\nfloat32[] intensities\n",
        {"std_msgs/Header"}}},
      {"sensor_msgs/PointField",
       {"uint8 INT8    = 1\nuint8 UINT8   = 2\nuint8 INT16   = 3\nuint8 UINT16  = 4\n"
        "uint8 INT32   = 5\nuint8 UINT32  = 6\nuint8 FLOAT32 = 7\nuint8 FLOAT64 = 8\n"
        "string name\nuint32 offset\nuint8  datatype\nuint32 count\n",
        {}}},
      {"sensor_msgs/PointCloud2",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\n"
        "bool    is_bigendian\nuint32  point_step\nuint32  row_step\nuint8[] data\n"
        "bool is_dense\n",
        {"std_msgs/Header", "sensor_msgs/PointField"}}},
      {"sensor_msgs/Image",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n"
        "uint8 is_bigendian\nuint32 step\nuint8[] data\n",
        {"std_msgs/Header"}}},
      {"sensor_msgs/RegionOfInterest",
       {"uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n", {}}},
      {"sensor_msgs/CameraInfo",
       {"std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
        "float64[] d\nfloat64[9]  k\nfloat64[9]  r\nfloat64[12] p\n"
        "uint32 binning_x\nuint32 binning_y\nRegionOfInterest roi\n",
        {"std_msgs/Header", "sensor_msgs/RegionOfInterest"}}},
      {"nav_msgs/Odometry",
       {"std_msgs/Header header\nstring child_frame_id\n"
        "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
        {"std_msgs/Header", "geometry_msgs/PoseWithCovariance",
         "geometry_msgs/TwistWithCovariance"}}},
      {"tf2_msgs/TFMessage",
       {"geometry_msgs/TransformStamped[] transforms\n", {"geometry_msgs/TransformStamped"}}},
  };
  return defs;
}

// The text without its final newline: the separator brings its own.
std::string body(const Definition& d) {
  std::string t = d.text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  return t;
}

// Depth-first, each dependency once, the order rosbag2's message definition source uses.
void appendDependencies(const Definition& d, std::set<std::string>& seen, std::string& out) {
  for (const char* dep : d.deps) {
    if (!seen.insert(dep).second) continue;
    const Definition& sub = definitions().at(dep);
    out += "\n================================================================================\n";
    out += "MSG: ";
    out += dep;
    out += "\n";
    out += body(sub);
    appendDependencies(sub, seen, out);
  }
}

std::string buildSchema(const std::string& short_name) {
  const Definition& root = definitions().at(short_name);
  std::string out = body(root);
  std::set<std::string> seen{short_name};
  appendDependencies(root, seen, out);
  return out;
}

}  // namespace

const std::string& ros2msgSchema(const std::string& type_name) {
  static const std::map<std::string, std::string> schemas = [] {
    std::map<std::string, std::string> m;
    for (const std::string& full : supportedTypes()) {
      // "pkg/msg/Type" -> "pkg/Type"
      std::string short_name = full.substr(0, full.find('/')) + full.substr(full.rfind('/'));
      m.emplace(full, buildSchema(short_name));
    }
    return m;
  }();
  auto it = schemas.find(type_name);
  if (it == schemas.end()) throw IoError(type_name + ": no ros2msg schema (not a supported type)");
  return it->second;
}

}  // namespace polyloc::msg
