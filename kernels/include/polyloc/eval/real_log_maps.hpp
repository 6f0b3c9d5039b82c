// The maps of the real-log protocol (docs/localization.md "Real logs: the robustness matrix"):
// the even scans of a log with known poses made into a polygon map in one of several ways, since
// a user's map comes from whatever tool they had, and a localiser tuned on one map build must hold
// on the others. Every style starts from the same scans at the same poses:
//
//   polyloc   polyloc's own: log-odds grid of 5 cm cells, a hit counted half a cell beyond the
//             end point (walls straddle the surface), extruded (`polyloc map extrude --carmen`)
//   endpoint  5 cm cells marked where end points fall, closed with a 3x3 kernel, extruded without
//             a half-cell correction: faces stand up to a cell proud of the surface
//   coarse    10 cm log-odds cells, hit in the end point's cell: faces up to 10 cm proud
//   dilated   polyloc's grid with every wall one cell thicker (faces 5 cm proud)
//   noisy     polyloc's mesh warped by a smooth 2 cm displacement field (map/mesh_warp.hpp):
//             walls bend by centimetres, as SLAM maps do
//
//   LogMap m = buildLogMap(log, split.map_scans, "endpoint", {});
//   m.mesh (walls 2 m on a floor slab), m.grid (what the mesh was extruded from)
#pragma once

#include <polyloc/eval/real_log.hpp>
#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/mesh.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace polyloc {

// The styles above, in that order.
const std::vector<std::string>& logMapStyles();
// One line per style, for --help and errors.
std::string describeLogMapStyle(const std::string& style);

struct LogMapOptions {
  double resolution = 0.05;     // m: the fine styles' cells (coarse: twice this)
  double max_range = 30.0;      // m: beams beyond are not mapped (ScanMapperConfig::max_range)
  double wall_height = 2.0;     // m
  double warp_sigma = 0.02;     // m: noisy
  double warp_correlation = 0.5;  // m: noisy
  uint64_t seed = 1;            // noisy
  std::function<void(double fraction)> progress;
};

struct LogMap {
  std::string style;
  OccupancyGrid grid;  // the grid the mesh was extruded from (noisy: before the warp)
  Mesh mesh;
  size_t scans_used = 0;
};

// Throws std::invalid_argument naming the style when it is not one of logMapStyles(), and
// std::runtime_error when no map scan could be used.
LogMap buildLogMap(const RealLog& log, const std::vector<size_t>& map_scans, const std::string& style,
                   const LogMapOptions& options = {});

}  // namespace polyloc
