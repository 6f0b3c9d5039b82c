#include <polyloc/map/grid_walk.hpp>
#include <polyloc/vrs/obstacle_memory.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace polyloc {

namespace {
int32_t wrap(int32_t v, int32_t n) { return ((v % n) + n) % n; }
}  // namespace

ObstacleMemory::ObstacleMemory(const ObstacleMemoryConfig& config) : config_(config) {
  if (!(config_.resolution > 0) || config_.cells < 8)
    throw std::invalid_argument("obstacle memory: resolution must be > 0 and cells >= 8");
  cells_.resize(size_t(config_.cells) * size_t(config_.cells));
  if ((config_.cells & (config_.cells - 1)) == 0) mask_ = config_.cells - 1;
}

ObstacleMemory::Cell* ObstacleMemory::slot(int32_t cx, int32_t cy) {
  return const_cast<Cell*>(&cellAt(cx, cy));
}

const ObstacleMemory::Cell& ObstacleMemory::cellAt(int32_t cx, int32_t cy) const {
  const int32_t n = config_.cells;
  if (mask_) return cells_[size_t(cy & mask_) * size_t(n) + size_t(cx & mask_)];
  return cells_[size_t(wrap(cy, n)) * size_t(n) + size_t(wrap(cx, n))];
}

const ObstacleMemory::Cell* ObstacleMemory::find(int32_t cx, int32_t cy) const {
  const Cell& c = cellAt(cx, cy);
  return c.cx == cx && c.cy == cy && alive(c) ? &c : nullptr;
}

void ObstacleMemory::advance(double dt, double speed, double turn_rate) {
  if (!(dt > 0) || !std::isfinite(dt)) return;
  if (!(std::abs(speed) > config_.moving_speed || std::abs(turn_rate) > config_.moving_turn_rate)) return;
  clock_ += dt;
  occupied_ = 0;
  for (Cell& c : cells_) {
    if (c.seen < 0) continue;
    if (!alive(c)) c.seen = -1;
    else ++occupied_;
  }
}

void ObstacleMemory::insert(const Eigen::Vector2f& p) {
  if (!p.allFinite()) return;
  const auto cx = int32_t(std::floor(p.x() / config_.resolution)), cy = int32_t(std::floor(p.y() / config_.resolution));
  Cell* c = slot(cx, cy);
  if (!alive(*c)) ++occupied_;  // a live slot holding another cell is overwritten: the newer wins
  *c = Cell{cx, cy, p.x(), p.y(), clock_};
}

float ObstacleMemory::castRay(const Eigen::Vector2f& origin, float angle, float limit) const {
  const float inf = std::numeric_limits<float>::infinity();
  if (occupied_ == 0 || !origin.allFinite()) return inf;
  // Past `limit` (what the direct sources already see) the memory cannot give a nearer range.
  const double res = config_.resolution, reach = std::min<double>(config_.max_distance, limit + res);
  const int32_t x0 = int32_t(std::floor(origin.x() / res)), y0 = int32_t(std::floor(origin.y() / res));
  const int32_t x1 = int32_t(std::floor((origin.x() + reach * std::cos(angle)) / res));
  const int32_t y1 = int32_t(std::floor((origin.y() + reach * std::sin(angle)) / res));
  // Bresenham from the robot's cell to the cell at max_distance; the first remembered point
  // (within reach) is the segment's range.
  float range = inf;
  walkCells(x0, y0, x1, y1, [&](int32_t cx, int32_t cy) {
    const Cell* c = find(cx, cy);
    if (!c) return false;
    const float d = std::hypot(c->x - origin.x(), c->y - origin.y());
    if (d <= reach) range = d;
    return d <= reach;
  });
  return range;
}

std::vector<Eigen::Vector2f> ObstacleMemory::points() const {
  std::vector<Eigen::Vector2f> out;
  for (const Cell& c : cells_)
    if (alive(c)) out.emplace_back(c.x, c.y);
  return out;
}

void ObstacleMemory::clear() {
  for (Cell& c : cells_) c.seen = -1;
  occupied_ = 0;
}

}  // namespace polyloc
