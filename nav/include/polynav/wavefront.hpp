// The global planner: a wavefront (Dijkstra) from the goal over the free cells of an inflated
// NavGrid, and the path from the start down the wave. Cells the VRS found blocked (an obstacle
// the map does not have) are left out until they age; door cells are never blocked, so a closed
// door is reported to the caller instead of being retried forever.
#pragma once

#include <polynav/nav_grid.hpp>

#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace polynav {

struct WavefrontConfig {
  bool eight_connected = true;  // diagonal steps too (never cutting an obstacle's corner)
  // Optional cost for passing near obstacles (0: the shortest path): a step into a cell at d < clearance_range (m)
  // from an obstacle costs its length x (1 + clearance_weight x (1 - d / clearance_range)).
  double clearance_weight = 0.0;
  double clearance_range = 0.5;
  double blocked_max_age_s = 30.0;  // what the controller passes to BlockedCells::age
};

// Cells found blocked, each with the time it was last found so.
class BlockedCells {
 public:
  // Blocks `cells` of `g` at `now_s` (refreshing the time of those already blocked), except door
  // cells: those are returned (in the order given) and not blocked. Throws std::invalid_argument
  // for a cell outside `g` or a time that is not finite.
  std::vector<size_t> block(const NavGrid& g, const std::vector<size_t>& cells, double now_s);
  // Forgets the cells blocked `max_age_s` or longer before `now_s`.
  void age(double now_s, double max_age_s);
  bool blocked(size_t cell) const { return cells_.count(cell) != 0; }
  size_t size() const { return cells_.size(); }
  const std::map<size_t, double>& cells() const { return cells_; }  // cell -> time last blocked (s)
  void clear() { cells_.clear(); }

 private:
  std::map<size_t, double> cells_;  // ordered: planning does not depend on hashing
};

struct WavefrontPlan {
  bool reachable = false;
  // Why not: "start outside the grid", "start in an obstacle", "goal outside the grid",
  // "goal in an obstacle", "goal in a blocked cell", "goal unreachable from the start".
  std::string why;
  // World points, start to goal: one per cell centre along the descent (the start cell's first),
  // the exact goal last in place of its cell's centre.
  std::vector<Eigen::Vector2d> path;
  double length_m = 0;                // of the polyline `path`
};

class Wavefront {
 public:
  explicit Wavefront(const WavefrontConfig& c = {});  // throws std::invalid_argument for a bad field

  // Costs from the goal over the free cells (occupied and blocked cells left out; the start cell
  // counts as free when only blocked: the robot stands in it) by Dijkstra, 4- or 8-connected (a
  // diagonal step costs sqrt(2) x resolution and needs both side cells free), with the clearance
  // cost; then the path from the start cell down the wave, each step to the neighbour the wave came
  // through (ties: the first in the fixed order E N W S NE NW SW SE), so one input gives one path.
  // Throws std::invalid_argument for a bad grid (NavGrid::validate) or a start/goal not finite.
  WavefrontPlan plan(const NavGrid& g, const BlockedCells& blocked, const Eigen::Vector2d& start,
                     const Eigen::Vector2d& goal);
  // Per cell, the last plan's cost to the goal (m, with the clearance cost); +inf where unreachable.
  const std::vector<double>& costs() const { return costs_; }
  const WavefrontConfig& config() const { return config_; }

 private:
  WavefrontConfig config_;
  std::vector<double> costs_;
};

// Whether any cell along the next `ahead_m` metres of `path` (from waypoint `from`) is occupied,
// blocked or outside the grid: the look-ahead check that triggers a replan. False when `from` is
// past the end. Throws std::invalid_argument for a bad grid, a path point not finite or a bad ahead_m.
bool pathBlocked(const NavGrid& g, const BlockedCells& b, const std::vector<Eigen::Vector2d>& path, size_t from,
                 double ahead_m);

}  // namespace polynav
