// A sensor rig: the sensors mounted on one robot, with names and mounts (base_link -> sensor).
// Rigs are plain YAML (docs/simulation.md); `lisa` and `taser` are built-in examples whose YAML
// form is maps/rigs/lisa.yaml and maps/rigs/taser.yaml.
//
//   name: taser
//   sensors:
//     - name: lms_front             # topic and frame name: letters, digits, '_'
//       preset: sick_lms200         # sensorPresetNames()
//       mount: {x: 0.33, y: 0, z: 0.2, roll: 0, pitch: 0, yaw: 0}   # metres, degrees
//       spec: {range_max: 8}        # optional: override fields of the preset (see rig.cpp)
#pragma once

#include <polyloc/config/yaml.hpp>
#include <polyloc/sensors/sensor.hpp>

#include <string>
#include <vector>

namespace polyloc {

struct Rig {
  std::string name;
  std::vector<Sensor> sensors;
  std::vector<std::string> presets;  // per sensor: the preset it was made from ("" if none)

  size_t size() const { return sensors.size(); }
  int find(const std::string& sensor_name) const;  // index, or -1
  // A planar scanner whose scan plane is within max_tilt (rad) of horizontal: what a 2D map
  // (grid2d, motion detection in the scan plane) can use.
  bool isLevelScanner(size_t i, double max_tilt = 10.0 * 3.14159265358979323846 / 180.0) const;
  void add(Sensor s, std::string preset) {
    sensors.push_back(std::move(s));
    presets.push_back(std::move(preset));
  }
};

// lisa: two SICK S300 on opposite corners 10 cm above the floor facing diagonally outwards
// (270 deg each, 360 deg together), four Hokuyo URG-04LX centred on the four sides at 1.0 m,
// pitched 40 deg down (a funnel around the robot), a PMD O3D100 facing forward, pitched 10 deg
// down. Footprint 0.6 m x 0.5 m. taser: two SICK LMS200 front and back, 20 cm above the floor,
// footprint 0.7 m x 0.6 m. Throws std::invalid_argument listing the known names.
Rig rigPreset(const std::string& name);
std::vector<std::string> rigPresetNames();

// A rig mapping {name, sensors}. Throws ConfigError naming file, line and key.
Rig parseRig(ConfigMap m);
Rig loadRig(const std::string& file);
// A `rig:` value: a preset name ("lisa"), a YAML file (relative to the file that names it), or
// an inline mapping.
Rig readRig(const ConfigValue& v, const ConfigMap& context);

// The mount as YAML reads it: {x, y, z} metres, {roll, pitch, yaw} degrees (or "x rad").
Pose parseMount(ConfigMap m);

}  // namespace polyloc
