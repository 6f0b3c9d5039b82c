// A mounted sensor: one of the models, its 6-DoF mount on the robot base (base_T_sensor),
// and a name. Presets are looked up by name ("sick_s300", "hokuyo_urg04lx", "sick_lms200",
// "vlp16", "pmd_o3d100").
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/depth_camera.hpp>
#include <polyloc/sensors/lidar.hpp>
#include <polyloc/sensors/planar_scanner.hpp>

#include <string>
#include <variant>
#include <vector>

namespace polyloc {

using SensorSpec = std::variant<PlanarScannerSpec, LidarSpec, DepthCameraSpec>;

struct Sensor {
  std::string name;
  SensorSpec spec;
  Pose mount;  // base_link -> sensor

  BeamSet beams() const;
  double rateHz() const;
  const char* typeName() const;  // "planar_scanner", "lidar", "depth_camera"
  // map_T_sensor for a robot at map_T_base.
  Pose worldPose(const Pose& map_T_base) const { return map_T_base * mount; }
};

// Throws std::invalid_argument naming the preset and listing the known ones.
SensorSpec sensorPreset(const std::string& preset);
std::vector<std::string> sensorPresetNames();

}  // namespace polyloc
