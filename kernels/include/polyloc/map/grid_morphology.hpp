// Morphology on the occupied cells of an occupancy grid (OpenCV), as map tools post-process scan
// maps: closing bridges the one-cell gaps between the end points of a wall seen at a grazing
// angle; dilation thickens every wall (a map whose walls stand a cell proud of the surfaces).
// Cells that become occupied are occupied whatever they were; no occupied cell is removed.
#pragma once

#include <polyloc/map/grid_map.hpp>

namespace polyloc {

// Closing (dilate, then erode) with a square kernel of `kernel` cells (odd, >= 1). Throws
// std::invalid_argument for an even or non-positive kernel.
OccupancyGrid closeOccupied(const OccupancyGrid& grid, int kernel = 3);

// Every cell within `cells` (Chebyshev distance) of an occupied cell becomes occupied.
OccupancyGrid dilateOccupied(const OccupancyGrid& grid, int cells = 1);

}  // namespace polyloc
