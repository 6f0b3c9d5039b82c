// The `depth_filter:` section of the polyloc config into DepthFilterConfig: nested `validity:`,
// `jump_edge:`, `confidence:`, `smoothing:` mappings with the fields' names as keys; angles in
// degrees (or "x rad"). docs/depth.md lists every key with its default.
#pragma once

#include <polyloc/config/yaml.hpp>
#include <polyloc/depth/config.hpp>

namespace polyloc {

// Throws ConfigError naming file, line and key (unknown keys, bad values).
DepthFilterConfig parseDepthFilterConfig(ConfigMap m);

}  // namespace polyloc
