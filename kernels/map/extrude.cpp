#include <polyloc/map/extrude.hpp>

#include <cmath>
#include <map>
#include <stdexcept>

namespace polyloc {

Mesh extrudeGrid(const OccupancyGrid& g, const ExtrudeOptions& o, ExtrudeStats* stats) {
  if (!(o.height > 0)) throw std::invalid_argument("extrude: height must be > 0");
  if (!(o.floor_thickness >= 0)) throw std::invalid_argument("extrude: floor thickness must be >= 0");
  if (!(g.resolution > 0) || g.cells.size() != g.width * g.height)
    throw std::invalid_argument("extrude: empty or inconsistent grid");
  Mesh m;
  m.source = "extruded grid";
  const uint32_t wall = m.labelId("wall"), floor = m.labelId("floor");
  const Eigen::Vector2d origin(g.origin_x, g.origin_y);
  const double r = g.resolution, e = 0.01 * r;
  const auto solid = [&](size_t x, size_t y) {
    const int8_t v = g.at(x, y);
    return v == OccupancyGrid::kOccupied || (o.unknown_is_occupied && v == OccupancyGrid::kUnknown);
  };
  ExtrudeStats st;
  // Open boxes by run [x0, x1] -> first row; a run continued in the next row stays open.
  std::map<std::pair<size_t, size_t>, size_t> open, next;
  const auto emit = [&](size_t x0, size_t x1, size_t y0, size_t y1) {
    m.addBox({double(x0) * r - e, double(y0) * r - e, 0.0},
             {double(x1 + 1) * r + e, double(y1 + 1) * r + e, o.height}, wall, origin, g.origin_yaw);
    ++st.boxes;
  };
  for (size_t y = 0; y <= g.height; ++y) {
    next.clear();
    if (y < g.height)
      for (size_t x = 0; x < g.width;) {
        if (!solid(x, y)) {
          ++x;
          continue;
        }
        size_t x1 = x;
        ++st.occupied_cells;
        while (o.merge && x1 + 1 < g.width && solid(x1 + 1, y)) ++x1, ++st.occupied_cells;
        const auto it = o.merge ? open.find({x, x1}) : open.end();
        next[{x, x1}] = it != open.end() ? it->second : y;
        if (it != open.end()) open.erase(it);
        x = x1 + 1;
      }
    for (const auto& [run, y0] : open) emit(run.first, run.second, y0, y - 1);
    open.swap(next);
  }
  if (o.floor_thickness > 0)
    m.addBox({0, 0, -o.floor_thickness}, {double(g.width) * r, double(g.height) * r, 0}, floor, origin,
             g.origin_yaw);
  if (stats) *stats = st;
  return m;
}

}  // namespace polyloc
