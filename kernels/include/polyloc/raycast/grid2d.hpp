// grid2d backend: a 2D occupancy grid at one height, the representation classic 2D MCL uses and
// the thesis's comparison for its BSP tree. Built by slicing the mesh at `height` (map/slice) and
// rasterising the segments; with fill_solids the cells inside closed solids are filled too
// (non-zero winding of the oriented slice polygons, one scanline per cell row), so a ray or
// point inside a wall reads solid as with the mesh. Or built from a ROS map_server grid.
//
// Rays: Bresenham's integer line walk from the cell of the window start; the range is where the
// ray enters the first occupied cell (ray/box slab test; the distance to the cell centre along
// the ray when the Bresenham cell only touches the ray), so a hit is off by less than one cell
// diagonal, typically under half a cell. The world is the slice extruded in z: a 3D ray is walked
// in its projection onto the plane and the planar range divided by the horizontal fraction of the
// direction (a ray steeper than 89.4 deg is a miss); ray origins' z is ignored. Results carry the
// triangle whose slice segment occupied the cell (kNoHit and label 0 for filled interior cells),
// and the normal of the cell face the ray entered.
//
// queryFree: the cell of the point is free and the Euclidean distance transform of the grid
// (centre to centre of the nearest occupied cell, minus half a cell) is >= clearance; z ignored.
#pragma once

#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/per_ray_caster.hpp>

#include <memory>
#include <span>

namespace polyloc {

struct Grid2dOptions {
  double resolution = 0.05;  // m per cell
  double height = 0.3;       // m, the slice (a sensor height); rays' own z is ignored
  double padding = 0.5;      // m of free cells around the mesh bounds
  bool fill_solids = true;   // fill the inside of closed solids (needs closed, outward meshes)
  int threads = 0;           // 0 = all cores
};

class Grid2dCaster final : public PerRayCaster {
 public:
  Grid2dCaster(const Mesh& mesh, const Grid2dOptions& options = {});
  // From a map grid; unknown cells count as free. The grid must not be rotated (origin yaw 0).
  explicit Grid2dCaster(const OccupancyGrid& grid, int threads = 0);
  ~Grid2dCaster() override;

  const char* name() const override { return "grid2d"; }
  void queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                 uint8_t* free) const override;

  size_t width() const;
  size_t height() const;
  double resolution() const;
  bool occupied(size_t x, size_t y) const;
  // Per cell (row-major, x fastest) the distance (m) to the nearest occupied cell, 0 in one;
  // cell (0, 0) has its corner at (originX(), originY()).
  std::span<const float> clearance() const;
  double originX() const;
  double originY() const;
  OccupancyGrid grid() const;  // as a map grid (origin at the grid corner, yaw 0)
  size_t memoryBytes() const override;  // cells, their triangles and the distance transform

 protected:
  void traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                float t0, float t1, const CastOptions& opt) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
