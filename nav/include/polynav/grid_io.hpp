// The controller's map: a ROS map_server grid (YAML + image, as `polyloc map navgrid` writes it:
// the map's obstacles from the floor to the robot's height) read into a NavGrid, with the danger
// mask beside it (OUT.danger.pgm: 0 where danger) when there is one.
#pragma once

#include <polynav/nav_grid.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace polynav {

class GridIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LoadedGrid {
  NavGrid grid;                 // occupied: map_server's occupied and unknown cells (never drive into the unknown)
  std::vector<uint8_t> danger;  // per cell, 1 where the danger mask says so; empty without a mask
};

// Reads `yaml_path` (keys image, resolution, origin [x, y, yaw], occupied_thresh, free_thresh,
// negate; mode trinary) and the image it names, and `<stem>.danger.pgm` next to it if present.
// Throws GridIoError naming the file and the key: missing file or key, resolution <= 0, a rotated
// origin (yaw != 0), an image that does not decode, a danger mask of another size.
LoadedGrid loadNavGrid(const std::string& yaml_path);

}  // namespace polynav
