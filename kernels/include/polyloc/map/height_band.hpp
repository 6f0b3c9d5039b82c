// A polygon map's free space for a ground robot, as a 2D occupancy grid (ROS map_server, through
// map/grid_map.hpp): a cell is occupied when any part of the world lies in it between the local
// floor + clearance and the local floor + the robot's height. Table tops, chair seats, shelves
// and overhangs below the robot's top count; thresholds and cables below the clearance, and lamps
// above the robot, do not. The grid is what a 2D planner needs to keep a robot of that height
// clear of obstacles at every height, the way the virtual range scan (vrs/) does at run time.
//
// Per cell (square of `resolution`, grid over the mesh's x/y bounds + padding):
//   floor    the highest walkable surface at the cell centre: a triangle with a floor label whose
//            slope is at most max_floor_slope_deg (ramps and platforms raise it). None -> the
//            robot cannot stand there (a stairwell, a shaft, outside the slab): occupied, or
//            unknown when the centre is outside the mesh's x/y bounds (the padding).
//   band     [floor + clearance, floor + height].
//   occupied any other triangle (and floor triangles steeper than the limit: the sides of a
//            platform or a ramp) whose part over the cell square (conservative: clipped to the
//            square, edges included) reaches into the band; a walkable surface lying wholly in
//            the band over the cell (a step up onto a platform); the band inside a solid (the
//            middle of a wall or cabinet thicker than a cell, whose faces are all outside the
//            band): the winding number of the surfaces above the band at the cell centre,
//            counted only where that column's surfaces close up (on an open mesh a lone quad
//            does not fill the space under it); or a drop: a 4-neighbour's floor lower by more
//            than clearance + resolution * tan(max_floor_slope) (a platform's edge, a ramp's
//            side, seen from the top). So the clearance is the step, up or down, that the robot
//            drives over.
//   danger   a triangle with a danger label projects onto the cell, at any height (the stairs
//            and the landing of a stairwell below the floor too), as the VRS's danger zones do.
// Everything is exact up to the cell raster; TBB runs blocks of rows, each writing its own cells,
// so the result is the same for any thread count.
#pragma once

#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/mesh.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace polyloc {

struct HeightBandOptions {
  double resolution = 0.05;  // m per cell, in (0, 1]
  double clearance = 0.06;   // m above the local floor: lower is floor (thresholds, cables); >= 0
  double height = 1.2;       // m, the robot's height above the local floor; > clearance
  double padding = 0.5;      // m of grid around the mesh's x/y bounds (unknown there); >= 0
  std::vector<std::string> floor_labels = {"floor", "ramp"};  // surfaces the robot drives on
  double max_floor_slope_deg = 15;  // steeper floor triangles are obstacles (in [0, 90))
  std::vector<std::string> danger_labels = {"danger"};  // projected into HeightBand::danger
};

struct HeightBandStats {
  size_t cells_occupied = 0, cells_free = 0, cells_unknown = 0;
  size_t cells_danger = 0;       // cells in the danger mask (occupied or not)
  size_t cells_no_floor = 0;     // cells with no walkable floor at their centre
  size_t cells_in_solid = 0;     // occupied only because the band is inside a closed solid
  size_t cells_drop = 0;         // occupied only because a neighbour's floor is lower by more than a step
  size_t open_columns = 0;       // cells whose surfaces above and below do not close up (open mesh)
  size_t triangles = 0;          // all of the mesh
  size_t floor_triangles = 0;    // walkable: floor label, slope within the limit, facing up
  size_t danger_triangles = 0;
};

struct HeightBand {
  OccupancyGrid grid;           // kFree, kOccupied, kUnknown per cell; origin_yaw 0
  std::vector<uint8_t> danger;  // 1 per cell (grid order): 1 where a danger triangle projects
  std::vector<float> floor_z;   // per cell: the floor height at its centre; NaN where none
};

// Throws std::invalid_argument naming the option and its value for bad options (resolution <= 0 or
// > 1, clearance < 0, height <= clearance, padding < 0, slope outside [0, 90), anything
// non-finite, no floor labels) and for a mesh with non-finite vertices; std::runtime_error naming
// the labels looked for and the labels the mesh has when no triangle is walkable floor, and naming
// the size when the grid would be over 20000 cells along x or y.
HeightBand heightBandGrid(const Mesh& mesh, const HeightBandOptions& options = {},
                          HeightBandStats* stats = nullptr);

// Writes the grid as a map_server YAML + PGM at `yaml_path` (saveGridMap) and, when any cell is
// danger, the danger mask beside it as `<stem>.danger.yaml` + `.pgm` (occupied where danger):
// what `polyloc map navgrid` writes and polynav's loadNavGrid reads. Returns the YAML paths
// written. Throws GridMapError on I/O errors.
std::vector<std::string> saveHeightBand(const HeightBand& band, const std::string& yaml_path);

}  // namespace polyloc
