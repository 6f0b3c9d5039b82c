// Danger zones: places the robot must not drive into although no sensor sees them (a stairwell,
// a loading edge): map triangles with a danger label, projected onto the floor, and polygons from
// the config. They are rasterised once into a grid (map frame) and read back per VRS segment by
// Bresenham, so they are permanent virtual obstacles at no cost per update.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

class DangerZones {
 public:
  DangerZones() = default;
  // Triangles of `map` whose label is in `labels`, and `polygons` (map frame, simple polygons of
  // at least 3 corners; others throw std::invalid_argument naming the polygon).
  DangerZones(const Mesh* map, const std::vector<std::string>& labels,
              const std::vector<std::vector<Eigen::Vector2d>>& polygons, double resolution);

  bool empty() const { return cells_.empty(); }
  // Distance from origin along `angle` to the first danger cell (its near edge), up to
  // max_distance; +inf when none. 0 when origin is inside a zone.
  float castRay(const Eigen::Vector2f& origin, float angle, float max_distance) const;
  bool inside(const Eigen::Vector2f& p) const;
  size_t cellCount() const;  // cells marked

 private:
  void markTriangle(const Eigen::Vector2f& a, const Eigen::Vector2f& b, const Eigen::Vector2f& c);
  void markPolygon(const std::vector<Eigen::Vector2f>& poly);
  bool at(int32_t cx, int32_t cy) const;

  double res_ = 0.05;
  Eigen::Vector2f lo_{0, 0};  // corner of cell (0, 0)
  int32_t nx_ = 0, ny_ = 0;
  std::vector<uint8_t> cells_;
};

}  // namespace polyloc
