// 2D occupancy grids as ROS map_server reads and writes them: an image (PGM, PNG, ...) and a YAML
// file naming it with `image`, `resolution`, `origin: [x, y, yaw]`, `occupied_thresh`,
// `free_thresh`, `negate` (and optionally `mode: trinary`). The grid backend of the ray caster and
// `polyloc map extrude` (grid -> 3D polygon map) use it.
//
// Semantics follow map_server's trinary mode: a pixel value v in [0, 255] has occupancy
// p = (255 - v) / 255 (p = v / 255 with negate: 1); p > occupied_thresh is occupied (100),
// p < free_thresh is free (0), anything between is unknown (-1). Image row 0 is the top of the
// picture, i.e. the largest y; cell (0, 0) of the grid is the bottom-left one, at `origin`.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace polyloc {

class GridMapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct OccupancyGrid {
  static constexpr int8_t kFree = 0, kOccupied = 100, kUnknown = -1;

  size_t width = 0, height = 0;  // cells along x and y
  double resolution = 0.05;      // m per cell
  double origin_x = 0, origin_y = 0, origin_yaw = 0;  // pose of cell (0, 0)'s outer corner
  std::vector<int8_t> cells;     // row-major from the bottom row (nav_msgs/OccupancyGrid order)

  int8_t at(size_t x, size_t y) const { return cells[y * width + x]; }
  int8_t& at(size_t x, size_t y) { return cells[y * width + x]; }
  bool occupied(size_t x, size_t y) const { return at(x, y) == kOccupied; }
  void resize(size_t w, size_t h, int8_t value = kFree) {
    width = w;
    height = h;
    cells.assign(w * h, value);
  }
};

struct GridSaveOptions {
  double occupied_thresh = 0.65;  // map_saver's defaults
  double free_thresh = 0.196;
};

// Reads the YAML and the image it names (relative to the YAML's folder). Throws GridMapError
// naming the file (and key, with line) for: a missing/unreadable file, a missing or bad key
// (resolution <= 0, thresholds outside [0, 1] or free >= occupied, origin not 3 numbers, negate
// not 0/1), an unsupported mode (only trinary), unknown keys, an image that cannot be decoded.
OccupancyGrid loadGridMap(const std::string& yaml_path);

// Writes YAML + binary PGM (P5) as map_saver does: occupied 0, free 254, unknown 205. The image
// goes next to the YAML with the same stem and extension .pgm. Throws GridMapError on I/O errors.
void saveGridMap(const OccupancyGrid& grid, const std::string& yaml_path,
                 const GridSaveOptions& options = {});

}  // namespace polyloc
