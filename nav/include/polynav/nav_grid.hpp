// The planning grid of a navigation controller: the map's free space as square cells, the map
// sliced from the floor to the robot's height (anything a robot would hit counts, at any height),
// optionally with the map's door labels. Inflating it by the robot's radius turns the robot into
// a point: a plan over the inflated grid keeps the whole footprint clear.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace polynav {

struct NavGrid {
  size_t width = 0, height = 0;       // cells along x and y
  double resolution = 0.05;           // m per cell
  double origin_x = 0, origin_y = 0;  // world position of cell (0, 0)'s outer corner; row-major from the bottom row
  std::vector<uint8_t> occupied;      // 1: an obstacle somewhere from the floor to the robot's height, 0 free
  std::vector<uint8_t> door;          // optional (empty or width * height): 1 where the map labels a door

  size_t size() const { return width * height; }
  size_t index(size_t ix, size_t iy) const { return iy * width + ix; }
  bool isDoor(size_t i) const { return !door.empty() && door[i]; }
  // The cell holding world point `p`; none outside the grid (or for a point that is not finite).
  std::optional<size_t> cellAt(const Eigen::Vector2d& p) const;
  Eigen::Vector2d centre(size_t ix, size_t iy) const;
  Eigen::Vector2d centre(size_t i) const { return centre(i % width, i / width); }
  // Throws std::invalid_argument naming the field and its value: resolution <= 0 or not finite,
  // an origin that is not finite, `occupied` or a non-empty `door` not of width * height cells.
  void validate() const;
};

// Per cell, the distance in metres from its centre to the nearest occupied cell's centre
// (0 in occupied cells, +inf everywhere when nothing is occupied).
std::vector<float> obstacleDistance(const NavGrid& g);

// `g` with every cell whose centre lies closer than `radius` (m) to an occupied cell's centre
// occupied too. Door flags are kept (a door cell may now be occupied: the robot does not fit).
NavGrid inflate(const NavGrid& g, double radius);

}  // namespace polynav
