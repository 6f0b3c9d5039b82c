// The `vrs:` section of the polyloc config into VrsConfig. Keys are the fields' names; angles in
// degrees (or "x rad"); nested `memory:`; `sources:` a list of {sensor, mode}; `danger_zones:` a
// list of polygons [[x, y], ...] in the map frame; `cones:` a list of cone sensors.
// docs/vrs.md lists every key with its default.
#pragma once

#include <polyloc/config/yaml.hpp>
#include <polyloc/vrs/config.hpp>

namespace polyloc {

// `robot_height`: the default when the section does not set it (robot.height). Throws ConfigError
// naming file, line and key.
VrsConfig parseVrsConfig(ConfigMap m, double robot_height);
VrsMode parseVrsMode(const ConfigValue& v);
const char* vrsModeName(VrsMode m);

}  // namespace polyloc
