// Exact 2D Euclidean distance transform of a cell grid (Felzenszwalb and Huttenlocher's lower
// envelope of parabolas, one pass per axis), for the clearance queries of grid2d.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace polyloc {

// occupied: nx * ny cells, row-major (x fastest). Returns per cell the distance in metres from
// its centre to the nearest occupied cell's centre minus half a cell (about the distance to that
// cell's boundary), 0 in occupied cells, +inf everywhere when nothing is occupied.
std::vector<float> gridDistanceTransform(const std::vector<uint8_t>& occupied, size_t nx,
                                         size_t ny, float resolution);

}  // namespace polyloc
