// The VRS obstacle memory: a 2D grid in the map frame that keeps obstacles a sensor saw only
// briefly (a tilted scanner passes over a table edge once). It wraps around (cell (i, j) lives at
// slot (i mod n, j mod n) and remembers which cell it holds), so it needs no recentring and its
// size is fixed. Each cell keeps the last point that entered it, so ranges read back are exact,
// not rounded to cells. Cells age on a motion clock that runs only while the robot moves.
#pragma once

#include <polyloc/vrs/config.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace polyloc {

class ObstacleMemory {
 public:
  explicit ObstacleMemory(const ObstacleMemoryConfig& config);

  // Advances the motion clock by dt when the robot moved (speed, turn rate) and forgets cells
  // older than the lifetime. Time going backwards or dt <= 0 advances nothing.
  void advance(double dt, double speed, double turn_rate);
  // A point (map frame, x/y) enters or refreshes its cell.
  void insert(const Eigen::Vector2f& p);
  // Nearest remembered point along the ray from `origin` in direction `angle` (map frame), walked
  // cell by cell (Bresenham) up to min(limit, max_distance); +inf when none. Returns the
  // distance of the stored point from origin.
  float castRay(const Eigen::Vector2f& origin, float angle, float limit = INFINITY) const;
  // Every remembered point (for plots and tests).
  std::vector<Eigen::Vector2f> points() const;
  size_t size() const { return occupied_; }
  double clock() const { return clock_; }
  void clear();

 private:
  struct Cell {
    int32_t cx = 0, cy = 0;  // the cell this slot holds
    float x = 0, y = 0;      // the last point in it
    double seen = -1;        // motion clock when last refreshed; < 0: empty
  };
  Cell* slot(int32_t cx, int32_t cy);
  const Cell* find(int32_t cx, int32_t cy) const;
  const Cell& cellAt(int32_t cx, int32_t cy) const;
  bool alive(const Cell& c) const { return c.seen >= 0 && clock_ - c.seen <= config_.lifetime; }

  ObstacleMemoryConfig config_;
  std::vector<Cell> cells_;
  int32_t mask_ = 0;  // cells - 1 when cells is a power of two (the default): wrap by masking
  size_t occupied_ = 0;
  double clock_ = 0;
};

}  // namespace polyloc
