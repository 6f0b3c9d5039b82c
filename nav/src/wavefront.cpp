#include <polynav/wavefront.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace polynav {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The fixed neighbour order (E N W S, then NE NW SW SE): ties in the descent go to the first.
constexpr int kDx[8] = {1, 0, -1, 0, 1, -1, -1, 1};
constexpr int kDy[8] = {0, 1, 0, -1, 1, 1, -1, -1};

std::string str(const Eigen::Vector2d& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

void requireFinite(const char* who, const char* what, const Eigen::Vector2d& p) {
  if (!p.allFinite()) throw std::invalid_argument(std::string(who) + ": " + what + " is not finite: " + str(p));
}

}  // namespace

std::vector<size_t> BlockedCells::block(const NavGrid& g, const std::vector<size_t>& cells, double now_s) {
  g.validate();
  if (!std::isfinite(now_s)) throw std::invalid_argument("BlockedCells::block: now_s is not finite: " +
                                                         std::to_string(now_s));
  for (size_t c : cells)
    if (c >= g.size())
      throw std::invalid_argument("BlockedCells::block: cell " + std::to_string(c) + " is outside the grid of " +
                                  std::to_string(g.size()) + " cells");
  std::vector<size_t> doors;
  for (size_t c : cells) {
    if (g.isDoor(c)) doors.push_back(c);
    else cells_[c] = now_s;
  }
  return doors;
}

void BlockedCells::age(double now_s, double max_age_s) {
  if (!std::isfinite(now_s) || std::isnan(max_age_s))
    throw std::invalid_argument("BlockedCells::age: now_s " + std::to_string(now_s) + " or max_age_s " +
                                std::to_string(max_age_s) + " is not a number");
  std::erase_if(cells_, [&](const auto& kv) { return now_s - kv.second >= max_age_s; });
}

Wavefront::Wavefront(const WavefrontConfig& c) : config_(c) {
  std::ostringstream s;
  if (!std::isfinite(c.clearance_weight) || c.clearance_weight < 0)
    s << "clearance_weight must be finite and >= 0, got " << c.clearance_weight;
  else if (!std::isfinite(c.clearance_range) || c.clearance_range <= 0)
    s << "clearance_range must be finite and > 0, got " << c.clearance_range;
  else if (std::isnan(c.blocked_max_age_s) || c.blocked_max_age_s < 0)
    s << "blocked_max_age_s must be >= 0, got " << c.blocked_max_age_s;
  if (!s.str().empty()) throw std::invalid_argument("WavefrontConfig: " + s.str());
}

WavefrontPlan Wavefront::plan(const NavGrid& g, const BlockedCells& blocked, const Eigen::Vector2d& start,
                              const Eigen::Vector2d& goal) {
  g.validate();
  requireFinite("Wavefront::plan", "start", start);
  requireFinite("Wavefront::plan", "goal", goal);
  costs_.assign(g.size(), kInf);
  auto fail = [](const char* why) {
    WavefrontPlan p;
    p.why = why;
    return p;
  };
  const auto s = g.cellAt(start), t = g.cellAt(goal);
  if (!s) return fail("start outside the grid");
  if (g.occupied[*s]) return fail("start in an obstacle");
  if (!t) return fail("goal outside the grid");
  if (g.occupied[*t]) return fail("goal in an obstacle");
  if (blocked.blocked(*t) && *t != *s) return fail("goal in a blocked cell");

  // Traversable cells: free and not blocked (a dense mask: the wave asks for every cell).
  std::vector<uint8_t> passable(g.size());
  for (size_t i = 0; i < g.size(); ++i) passable[i] = !g.occupied[i];
  for (const auto& [c, _] : blocked.cells())
    if (c < g.size()) passable[c] = 0;
  passable[*s] = 1;
  // Per cell, the factor on a step's length into it (1 without the clearance cost).
  std::vector<double> factor(g.size(), 1.0);
  if (config_.clearance_weight > 0) {
    NavGrid obstacles = g;
    for (size_t i = 0; i < g.size(); ++i) obstacles.occupied[i] = !passable[i];
    const std::vector<float> d = obstacleDistance(obstacles);
    for (size_t i = 0; i < g.size(); ++i)
      if (d[i] < config_.clearance_range)
        factor[i] += config_.clearance_weight * (1.0 - d[i] / config_.clearance_range);
  }

  const int n_dirs = config_.eight_connected ? 8 : 4;
  const double step[2] = {g.resolution, std::sqrt(2.0) * g.resolution};
  // The neighbour of `c` in direction k, if it may be stepped between (both side cells of a
  // diagonal open); SIZE_MAX if not.
  auto neighbour = [&](size_t c, int k) -> size_t {
    const long x = long(c % g.width) + kDx[k], y = long(c / g.width) + kDy[k];
    if (x < 0 || y < 0 || x >= long(g.width) || y >= long(g.height)) return SIZE_MAX;
    const size_t n = g.index(size_t(x), size_t(y));
    if (!passable[n]) return SIZE_MAX;
    const size_t cx = c % g.width, cy = c / g.width;
    const bool sides = k < 4 || (passable[g.index(size_t(x), cy)] && passable[g.index(cx, size_t(y))]);
    return sides ? n : SIZE_MAX;
  };

  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  costs_[*t] = 0;
  queue.push({0.0, *t});
  while (!queue.empty()) {
    const auto [cost, c] = queue.top();
    queue.pop();
    if (cost > costs_[c]) continue;  // a stale entry
    for (int k = 0; k < n_dirs; ++k) {
      const size_t n = neighbour(c, k);
      if (n == SIZE_MAX) continue;
      const double next = cost + step[k >= 4] * factor[c];  // the robot steps from n into c
      if (next < costs_[n]) {
        costs_[n] = next;
        queue.push({next, n});
      }
    }
  }
  if (!std::isfinite(costs_[*s])) return fail("goal unreachable from the start");

  // Down the wave: the neighbour the cheapest way came through (cost + the step into this cell).
  // A small tolerance makes exact ties (rounded differently) go to the first in the fixed order.
  WavefrontPlan out;
  size_t c = *s;
  out.path.push_back(g.centre(c));
  for (size_t guard = 0; c != *t && guard < g.size(); ++guard) {
    size_t best = SIZE_MAX;
    double best_cost = kInf;
    for (int k = 0; k < n_dirs; ++k) {
      const size_t n = neighbour(c, k);
      if (n == SIZE_MAX || !std::isfinite(costs_[n])) continue;
      const double via = costs_[n] + step[k >= 4] * factor[n];
      if (via < best_cost - 1e-9) best = n, best_cost = via;
    }
    if (best == SIZE_MAX || !(costs_[best] < costs_[c])) break;  // cannot happen on a consistent wave
    c = best;
    out.path.push_back(g.centre(c));
  }
  if (c != *t) return fail("goal unreachable from the start");
  out.path.back() = goal;
  for (size_t i = 1; i < out.path.size(); ++i) out.length_m += (out.path[i] - out.path[i - 1]).norm();
  out.reachable = true;
  return out;
}

bool pathBlocked(const NavGrid& g, const BlockedCells& b, const std::vector<Eigen::Vector2d>& path, size_t from,
                 double ahead_m) {
  g.validate();
  if (std::isnan(ahead_m) || ahead_m < 0)
    throw std::invalid_argument("pathBlocked: ahead_m must be >= 0, got " + std::to_string(ahead_m));
  for (size_t i = from; i < path.size(); ++i) requireFinite("pathBlocked", "path point", path[i]);
  auto bad = [&](const Eigen::Vector2d& p) {
    const auto c = g.cellAt(p);
    return !c || g.occupied[*c] || b.blocked(*c);
  };
  if (from >= path.size()) return false;
  if (bad(path[from])) return true;
  // Samples at most half a cell apart along each segment, until ahead_m is used up.
  double left = ahead_m;
  for (size_t i = from + 1; i < path.size() && left > 0; ++i) {
    const Eigen::Vector2d a = path[i - 1], d = path[i] - a;
    const double len = d.norm(), use = std::min(len, left);
    const int n = int(std::ceil(use / (0.5 * g.resolution)));
    for (int j = 1; j <= n; ++j)
      if (bad(a + d * (use / len * j / n))) return true;
    left -= use;
  }
  return false;
}

}  // namespace polynav
