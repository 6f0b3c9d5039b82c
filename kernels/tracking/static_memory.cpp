#include <polyloc/tracking/static_memory.hpp>

#include <cmath>
#include <stdexcept>

namespace polyloc {

StaticMemory::StaticMemory(double cell_m, double time_s, double gap_s)
    : inv_cell_(1.0 / cell_m), time_ns_(std::llround(time_s * 1e9)), gap_ns_(std::llround(gap_s * 1e9)) {
  if (!(cell_m > 0)) throw std::invalid_argument("static memory: cell size must be > 0");
}

uint64_t StaticMemory::key(const Eigen::Vector2d& p) const {
  // 32 bits per axis: +-214 km at 0.1 m cells.
  const auto ix = static_cast<int32_t>(std::floor(p.x() * inv_cell_));
  const auto iy = static_cast<int32_t>(std::floor(p.y() * inv_cell_));
  return (uint64_t(uint32_t(ix)) << 32) | uint64_t(uint32_t(iy));
}

bool StaticMemory::isStatic(const Eigen::Vector2d& p, int64_t stamp_ns) const {
  // The cell and its neighbours: a grazed edge is hit a little to either side each time.
  const double h = 1.0 / inv_cell_;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const auto it = cells_.find(key(p + Eigen::Vector2d(dx * h, dy * h)));
      if (it == cells_.end()) continue;
      const Cell& c = it->second;
      if (stamp_ns - c.last_ns <= gap_ns_ && c.last_ns - c.first_ns >= time_ns_) return true;
    }
  return false;
}

void StaticMemory::hit(const Eigen::Vector2d& p, int64_t stamp_ns) {
  Cell& c = cells_[key(p)];
  if (c.last_ns == 0 || stamp_ns - c.last_ns > gap_ns_) c.first_ns = stamp_ns;
  c.last_ns = stamp_ns;
}

void StaticMemory::forget(int64_t stamp_ns) {
  std::erase_if(cells_, [&](const auto& kv) { return stamp_ns - kv.second.last_ns > gap_ns_; });
}

}  // namespace polyloc
