// Ray casters by name, for the config, the CLI and the map-representation benchmark. One place
// lists the backends: add a new one to kCasterNames and to makeCaster (factory.cpp).
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/ray_caster.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace polyloc {

// The few knobs the backends share; each backend keeps its own full options struct.
struct CasterOptions {
  int threads = 0;           // 0 = all cores
  double resolution = 0.05;  // m: cell / voxel / node size of grid2d, distance3d, octomap
  double height = 0.3;       // m: slice height of grid2d
  // gpu: the EGL platforms to try, and whether a GPU that cannot be used (no EGL display, no
  // compute shaders, out of memory, a lost context) falls back to Embree with a warning instead
  // of an error. warn: where the warning goes (null: stderr).
  std::string gpu_platforms = "surfaceless,device,default";
  bool gpu_fallback = false;
  std::function<void(const std::string&)> warn;
};

// "embree", "bsp", "grid2d", "distance3d", "octomap", and "gpu" when built with POLYLOC_GPU:
// every backend makeCaster builds.
const std::vector<std::string>& casterNames();

// Throws std::invalid_argument for an unknown name (listing the known ones) and whatever the
// backend's constructor throws for a map it cannot take.
std::unique_ptr<RayCaster> makeCaster(const std::string& name, const Mesh& mesh,
                                      const CasterOptions& options = {});

}  // namespace polyloc
