// A 2D occupancy grid (map/grid_map) turned into a 3D polygon map, as the thesis built its
// simulation worlds: every occupied cell becomes a wall from z = 0 to `height`, on a floor slab
// under the whole grid. Runs of occupied cells are merged into boxes (greedy: runs along x, then
// identical runs in consecutive rows stacked), so a straight wall costs 12 triangles, not 12 per
// cell. Each box is a closed, outward-facing solid with its own vertices; boxes overlap their
// neighbours by 1 % of a cell so that no two share a vertex position (a loader welding identical
// vertices would otherwise join them into non-manifold edges) and no ray slips between them.
#pragma once

#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/mesh.hpp>

namespace polyloc {

struct ExtrudeOptions {
  double height = 2.0;            // m, wall height above z = 0
  double floor_thickness = 0.1;   // m, slab from -thickness to 0 under the grid; 0 = no floor
  bool merge = true;              // merge runs of cells into boxes (false: one box per cell)
  bool unknown_is_occupied = false;  // unknown cells become walls too
};

struct ExtrudeStats {
  size_t occupied_cells = 0;
  size_t boxes = 0;  // wall boxes (the floor not counted)
};

// Labels: "wall", "floor". Throws std::invalid_argument for height <= 0, a negative floor
// thickness or an inconsistent grid.
Mesh extrudeGrid(const OccupancyGrid& grid, const ExtrudeOptions& options = {},
                 ExtrudeStats* stats = nullptr);

}  // namespace polyloc
