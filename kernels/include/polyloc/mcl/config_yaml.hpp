// The `mcl:` section of the polyloc config (maps/config/*.yaml) into MclConfig. Every key is a
// field of MclConfig under the same name; nested `motion:` and `beam:` mappings; angles in
// degrees (or "x rad"). docs/localization.md lists them with defaults.
#pragma once

#include <polyloc/config/yaml.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/sensors/rig.hpp>

namespace polyloc {

// Throws ConfigError naming file, line and key (unknown keys, bad values; with the rig, also
// mcl.sensors it lacks or a grid2d caster without a level scanner).
// Keys absent from `m` keep their value in `defaults`.
MclConfig parseMclConfig(ConfigMap m, const Rig* rig = nullptr, const MclConfig& defaults = {});

}  // namespace polyloc
