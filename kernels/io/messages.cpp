#include <polyloc/io/messages.hpp>

namespace polyloc::msg {

const std::vector<std::string>& supportedTypes() {
  static const std::vector<std::string> names = {
      "sensor_msgs/msg/LaserScan", "sensor_msgs/msg/PointCloud2", "sensor_msgs/msg/Image",
      "sensor_msgs/msg/CameraInfo", "nav_msgs/msg/Odometry",       "tf2_msgs/msg/TFMessage",
      "geometry_msgs/msg/PoseStamped", "polyloc_msgs/msg/TrackArray",
      "geometry_msgs/msg/PoseWithCovarianceStamped"};
  return names;
}

const char* typeName(const Message& m) { return supportedTypes()[m.index()].c_str(); }

}  // namespace polyloc::msg
