#include <polyloc/eval/real_log_maps.hpp>
#include <polyloc/map/extrude.hpp>
#include <polyloc/map/grid_morphology.hpp>
#include <polyloc/map/mesh_warp.hpp>
#include <polyloc/map/scan_mapper.hpp>

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace polyloc {
namespace {

struct StyleInfo {
  const char* name;
  const char* description;
};
constexpr StyleInfo kStyles[] = {
    {"polyloc", "5 cm log-odds grid, hits half a cell beyond the end point (walls on the surface), extruded"},
    {"endpoint", "5 cm cells where end points fall, closed 3x3, no half-cell correction (faces up to a cell proud)"},
    {"coarse", "10 cm log-odds grid, hits in the end point's cell (faces up to 10 cm proud)"},
    {"dilated", "polyloc's grid with walls one cell thicker (faces 5 cm proud)"},
    {"noisy", "polyloc's mesh warped by a smooth 2 cm displacement field (walls bend by centimetres)"},
};

OccupancyGrid scanGrid(const RealLog& log, const std::vector<size_t>& scans, const ScanMapperConfig& mc,
                       const LogMapOptions& o, size_t& used) {
  ScanMapper mapper(mc);
  for (size_t k = 0; k < scans.size(); ++k) {
    const LoggedScan& s = log.scans[scans[k]];
    mapper.add(s.pose.x(), s.pose.y(), s.pose.yaw(), s.scan.ranges.data(), s.scan.ranges.size(), s.scan.angle_min,
               s.scan.angle_increment, s.scan.range_min, s.scan.range_max);
    if (o.progress && k % 16 == 0) o.progress(double(k) / double(scans.size()));
  }
  used = mapper.scans();
  if (used == 0) throw std::runtime_error(fmt::format("{}: no map scan could be used", log.path));
  return mapper.grid();
}

}  // namespace

const std::vector<std::string>& logMapStyles() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& s : kStyles) v.push_back(s.name);
    return v;
  }();
  return names;
}

std::string describeLogMapStyle(const std::string& style) {
  for (const auto& s : kStyles)
    if (style == s.name) return s.description;
  return "";
}

LogMap buildLogMap(const RealLog& log, const std::vector<size_t>& map_scans, const std::string& style,
                   const LogMapOptions& o) {
  const auto& names = logMapStyles();
  if (std::find(names.begin(), names.end(), style) == names.end())
    throw std::invalid_argument(fmt::format("unknown map style '{}' ({})", style, fmt::join(names, ", ")));
  LogMap m;
  m.style = style;
  ScanMapperConfig mc;
  mc.resolution = o.resolution;
  mc.max_range = o.max_range;
  if (style == "endpoint") mc.hit_beyond = 0, mc.sticky_hits = true;
  if (style == "coarse") mc.hit_beyond = 0, mc.resolution = 2 * o.resolution;
  m.grid = scanGrid(log, map_scans, mc, o, m.scans_used);
  if (style == "endpoint") m.grid = closeOccupied(m.grid, 3);
  if (style == "dilated") m.grid = dilateOccupied(m.grid, 1);
  ExtrudeOptions eo;
  eo.height = o.wall_height;
  m.mesh = extrudeGrid(m.grid, eo);
  if (style == "noisy") m.mesh = warpMesh(m.mesh, {o.warp_sigma, o.warp_correlation, o.seed});
  m.mesh.source = fmt::format("{} ({} map)", log.path, style);
  return m;
}

}  // namespace polyloc
