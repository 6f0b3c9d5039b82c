// The polyloc configuration file (maps/config/lab.yaml, office.yaml): one YAML file with a
// section per concept: map, robot, rig, mcl, tracking; later issues add vrs (add its parser to
// loadConfig, so unknown sections stay errors).
//
//   map: ../lab.obj                   # or {file: ..., scale: 1.0, up_axis: z}
//   robot: {...}                      # polyloc/config/robot.hpp
//   rig: ../rigs/lisa.yaml            # a preset name, a rig file, or inline (sensors/rig.hpp)
//   mcl: {...}                        # polyloc/mcl/config_yaml.hpp, docs/localization.md
//   vrs: {...}                        # polyloc/vrs/config_yaml.hpp, docs/vrs.md
//   tracking: {...}                   # polyloc/tracking/config_yaml.hpp, docs/tracking.md
//   depth_filter: {...}               # polyloc/depth/config_yaml.hpp, docs/depth.md
//   polylocd: {...}                   # read by polylocd only (service/pipeline/daemon_config.hpp)
#pragma once

#include <polyloc/config/robot.hpp>
#include <polyloc/config/yaml.hpp>
#include <polyloc/depth/config.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/sensors/rig.hpp>
#include <polyloc/vrs/config.hpp>
#include <polyloc/tracking/config.hpp>

#include <string>

namespace polyloc {

struct MapConfig {
  std::string file;      // resolved path (relative to the config file's directory when given so)
  LoadOptions load;      // scale, up_axis, merge_vertices
};

struct PolylocConfig {
  std::string file;  // where it was read from
  MapConfig map;     // file empty: none given (only with ConfigLoad::map_optional)
  RobotSpec robot;
  Rig rig;
  // `rig: recorded` (or no rig, with ConfigLoad::recorded_rig): the rig is made from the
  // recording being localised (reloc/recorded_rig.hpp); `rig` is empty until then.
  bool rig_from_recording = false;
  MclConfig mcl;  // `mcl:` section (polyloc/mcl/config_yaml.hpp); defaults when absent
  VrsConfig vrs;  // `vrs:` section (polyloc/vrs/config_yaml.hpp); robot_height from robot.height
  TrackingConfig tracking;  // `tracking:` section (polyloc/tracking/config_yaml.hpp); defaults when absent
  DepthFilterConfig depth_filter;  // `depth_filter:` section (polyloc/depth/config_yaml.hpp)
};

// What a command can do without: the map (it takes --map) and the rig (it reads the geometry
// from a recording: localize, relocalize, eval carmen).
struct ConfigLoad {
  bool map_optional = false;
  bool recorded_rig = false;
};

// The clearance a particle's body needs: the robot's inscribed radius less mcl.clearance_margin
// (one robot size rules; loadConfig sets mcl.clearance to this).
double particleClearance(const RobotSpec& robot, const MclConfig& mcl);

// Sets c.robot and what the other sections take from it, so that a robot is stated once: the
// particles' clearance, the motion model's drive (robot.kinematics) and the VRS's robot height
// when it was the old robot's (a vrs.robot_height of its own stays). loadConfig uses it; so does
// a scenario that replaces the robot of its config.
void applyRobot(PolylocConfig& c, const RobotSpec& robot);

// Throws ConfigError naming file, line and key (also when the map file does not exist, and for a
// missing map or a recorded rig that `load` does not allow).
PolylocConfig loadConfig(const std::string& path, const ConfigLoad& load = {});
// The depth filter settings of a file: a whole polyloc config (it has a `map`), or a file holding
// just a `depth_filter:` section (or nothing: the defaults). Throws ConfigError naming file:line:key.
DepthFilterConfig loadDepthFilterConfig(const std::string& path);

// Sections, for files that embed or override them (scenarios). readMapConfig takes the `map`
// value (a path or a mapping) and checks that the file exists.
MapConfig readMapConfig(const ConfigValue& v, const ConfigMap& context);

}  // namespace polyloc
