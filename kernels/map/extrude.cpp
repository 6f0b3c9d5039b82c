#include <polyloc/map/extrude.hpp>

#include <cmath>
#include <map>
#include <stdexcept>

namespace polyloc {
namespace {

struct Frame {
  double ox, oy, c, s;  // grid origin and yaw
  Eigen::Vector3f operator()(double x, double y, double z) const {
    return {float(ox + c * x - s * y), float(oy + s * x + c * y), float(z)};
  }
};

// Box [x0, x1] x [y0, y1] x [z0, z1] in grid-local metres; 12 triangles, counter-clockwise seen
// from outside.
void addBox(Mesh& m, const Frame& f, double x0, double y0, double z0, double x1, double y1,
            double z1, uint32_t label) {
  const uint32_t b = uint32_t(m.vertices.size());
  for (int k = 0; k < 8; ++k)
    m.vertices.push_back(f(k & 1 ? x1 : x0, k & 2 ? y1 : y0, k & 4 ? z1 : z0));
  // Vertex k: bit 0 = x, bit 1 = y, bit 2 = z. Quads listed counter-clockwise from outside.
  static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({b + q[0], b + q[1], b + q[2]});
    m.triangles.push_back({b + q[0], b + q[2], b + q[3]});
    m.triangle_label.push_back(label);
    m.triangle_label.push_back(label);
  }
}

}  // namespace

Mesh extrudeGrid(const OccupancyGrid& g, const ExtrudeOptions& o, ExtrudeStats* stats) {
  if (!(o.height > 0)) throw std::invalid_argument("extrude: height must be > 0");
  if (!(o.floor_thickness >= 0)) throw std::invalid_argument("extrude: floor thickness must be >= 0");
  if (!(g.resolution > 0) || g.cells.size() != g.width * g.height)
    throw std::invalid_argument("extrude: empty or inconsistent grid");
  Mesh m;
  m.source = "extruded grid";
  const uint32_t wall = m.labelId("wall"), floor = m.labelId("floor");
  const Frame f{g.origin_x, g.origin_y, std::cos(g.origin_yaw), std::sin(g.origin_yaw)};
  const double r = g.resolution, e = 0.01 * r;
  const auto solid = [&](size_t x, size_t y) {
    const int8_t v = g.at(x, y);
    return v == OccupancyGrid::kOccupied || (o.unknown_is_occupied && v == OccupancyGrid::kUnknown);
  };
  ExtrudeStats st;
  // Open boxes by run [x0, x1] -> first row; a run continued in the next row stays open.
  std::map<std::pair<size_t, size_t>, size_t> open, next;
  const auto emit = [&](size_t x0, size_t x1, size_t y0, size_t y1) {
    addBox(m, f, double(x0) * r - e, double(y0) * r - e, 0.0, double(x1 + 1) * r + e,
           double(y1 + 1) * r + e, o.height, wall);
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
    addBox(m, f, 0, 0, -o.floor_thickness, double(g.width) * r, double(g.height) * r, 0, floor);
  if (stats) *stats = st;
  return m;
}

}  // namespace polyloc
