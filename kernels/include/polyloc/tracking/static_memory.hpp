// Which places hold something static, from how long they have been hit: a grid cell hit on and
// off for `time` seconds, never left unhit for `gap` seconds in between, is static. A person
// walking past occupies a cell for a fraction of a second; a surface that flickers in and out of
// a low scan plane (a shelf's bottom board as the robot rolls) is hit again and again. Cells
// live in a hash map and are forgotten `gap` after their last hit, so memory follows the robot.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>

namespace polyloc {

class StaticMemory {
 public:
  StaticMemory(double cell_m, double time_s, double gap_s);
  // Whether the cell of p has been static at stamp_ns (hits up to now, not counting this one).
  bool isStatic(const Eigen::Vector2d& p, int64_t stamp_ns) const;
  void hit(const Eigen::Vector2d& p, int64_t stamp_ns);
  void forget(int64_t stamp_ns);  // drops cells not hit for `gap`
  void clear() { cells_.clear(); }
  size_t size() const { return cells_.size(); }

 private:
  struct Cell {
    int64_t first_ns = 0, last_ns = 0;  // the current run of hits
  };
  uint64_t key(const Eigen::Vector2d& p) const;
  double inv_cell_;
  int64_t time_ns_, gap_ns_;
  std::unordered_map<uint64_t, Cell> cells_;
};

}  // namespace polyloc
