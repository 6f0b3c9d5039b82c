// Ray casters by name, for the config, the CLI and the map-representation benchmark. One place
// lists the backends: add a new one to kCasterNames and to makeCaster (factory.cpp).
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/ray_caster.hpp>

#include <memory>
#include <string>
#include <vector>

namespace polyloc {

// The few knobs the backends share; each backend keeps its own full options struct.
struct CasterOptions {
  int threads = 0;           // 0 = all cores
  double resolution = 0.05;  // m: cell / voxel / node size of grid2d, distance3d, octomap
  double height = 0.3;       // m: slice height of grid2d
};

// "embree", "bsp", "grid2d", "distance3d", "octomap": every backend makeCaster builds.
const std::vector<std::string>& casterNames();

// Throws std::invalid_argument for an unknown name (listing the known ones) and whatever the
// backend's constructor throws for a map it cannot take.
std::unique_ptr<RayCaster> makeCaster(const std::string& name, const Mesh& mesh,
                                      const CasterOptions& options = {});

}  // namespace polyloc
