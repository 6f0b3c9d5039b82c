// The `tracking:` section of the polyloc config (maps/config/*.yaml) into TrackingConfig. Every
// key is a field of TrackingConfig under the same name, with nested `motion:`, `cluster:` and
// `tracker:` mappings; docs/tracking.md lists them with defaults.
#pragma once

#include <polyloc/config/yaml.hpp>
#include <polyloc/sensors/rig.hpp>
#include <polyloc/tracking/config.hpp>

namespace polyloc {

// Throws ConfigError naming file, line and key (unknown keys, bad values; with a rig also sensor
// names that are not level planar scanners of it).
TrackingConfig parseTrackingConfig(ConfigMap m, const Rig* rig = nullptr);

}  // namespace polyloc
