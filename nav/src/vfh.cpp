#include <polynav/vfh.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace polynav {

namespace {

constexpr double kPi = M_PI;

double wrap(double a) { return std::remainder(a, 2 * kPi); }

void validate(const Eigen::Vector2d& goal, const VfhConfig& c) {
  std::ostringstream s;
  if (!goal.allFinite()) s << "goal_in_base is not finite: (" << goal.x() << ", " << goal.y() << ")";
  else if (!(c.sector_deg > 0 && c.sector_deg <= 90)) s << "VfhConfig: sector_deg must be in (0, 90], got " << c.sector_deg;
  else if (!(c.window_m > 0) || !std::isfinite(c.window_m))
    s << "VfhConfig: window_m must be finite and > 0, got " << c.window_m;
  else if (!(c.threshold >= 0 && c.threshold < 1)) s << "VfhConfig: threshold must be in [0, 1), got " << c.threshold;
  else if (!(c.margin >= 0) || !std::isfinite(c.margin)) s << "VfhConfig: margin must be finite and >= 0, got " << c.margin;
  else if (!(c.wide_valley_deg > 0) || !std::isfinite(c.wide_valley_deg))
    s << "VfhConfig: wide_valley_deg must be finite and > 0, got " << c.wide_valley_deg;
  if (!s.str().empty()) throw std::invalid_argument("vfh: " + s.str());
}

}  // namespace

LocalCommand vfh(const PolarScan& scan, const Eigen::Vector2d& goal, const RectHull& hull, const VfhConfig& config,
                 const NdLimits& limits) {
  validate(goal, config);
  scan.validate("vfh");
  hull.validate();
  limits.validate("vfh");
  const long sectors = std::max(4L, std::lround(360.0 / config.sector_deg));
  const double step = 2 * kPi / double(sectors), radius = hull.width() / 2 + config.margin;
  auto sectorOf = [&](long k) { return size_t(((k % sectors) + sectors) % sectors); };

  // The polar histogram: per sector, the largest nearness covering its centre.
  std::vector<double> h(size_t(sectors), 0.0);
  double min_clear = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < scan.size(); ++i) {
    if (!scan.hit(i)) continue;
    const double a = scan.angle(i), r = scan.range(i), clear = std::max(0.0, hull.clearance(a, r));
    min_clear = std::min(min_clear, clear);
    if (clear >= config.window_m) continue;
    const double m = 1 - clear / config.window_m;
    const double spread = r > radius ? std::asin(radius / r) : kPi / 2;
    for (long k = long(std::ceil((a - spread) / step)); k <= long(std::floor((a + spread) / step)); ++k)
      h[sectorOf(k)] = std::max(h[sectorOf(k)], m);
  }

  LocalCommand out;
  out.min_clearance = min_clear;
  if (goal.norm() == 0) return out;  // there already
  const double goal_angle = std::atan2(goal.y(), goal.x());
  const size_t goal_sector = sectorOf(std::lround(goal_angle / step));
  auto blocked = [&](size_t k) { return h[k] > config.threshold; };
  long first_blocked = -1;
  for (long k = 0; k < sectors && first_blocked < 0; ++k)
    if (blocked(size_t(k))) first_blocked = k;

  double best = goal_angle;  // all free: straight at the goal
  if (first_blocked >= 0) {
    double best_cost = std::numeric_limits<double>::infinity();
    auto offer = [&](double c) {
      const double cost = std::abs(wrap(c - goal_angle));
      if (cost < best_cost - 1e-12 || (cost < best_cost + 1e-12 && std::abs(wrap(c)) < std::abs(wrap(best)))) {
        best_cost = cost;
        best = c;
      }
    };
    // Runs of free sectors, walked once around from a blocked one so that none is split.
    for (long k = first_blocked + 1; k <= first_blocked + sectors;) {
      if (blocked(sectorOf(k))) {
        ++k;
        continue;
      }
      long e = k;
      bool has_goal = false;
      for (; e < first_blocked + sectors && !blocked(sectorOf(e)); ++e) has_goal |= sectorOf(e) == goal_sector;
      const double lo = double(k) * step, hi = double(e - 1) * step;  // centres of the run's end sectors
      if (has_goal) offer(goal_angle);
      if (double(e - k) * step > config.wide_valley_deg * kPi / 180) {
        offer(lo + config.wide_valley_deg * kPi / 360);
        offer(hi - config.wide_valley_deg * kPi / 360);
      } else {
        offer((lo + hi) / 2);
      }
      k = e;
    }
    if (best_cost == std::numeric_limits<double>::infinity()) {
      out.blocked = true;
      out.direction = wrap(goal_angle);
      return out;
    }
  }
  const LocalCommand c = steer(best, 1 - h[sectorOf(std::lround(wrap(best) / step))], limits);
  out.v = c.v, out.w = c.w, out.direction = c.direction;
  return out;
}

}  // namespace polynav
