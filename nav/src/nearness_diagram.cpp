#include <polynav/nearness_diagram.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace polynav {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = M_PI;

double wrap(double a) { return std::remainder(a, 2 * kPi); }  // [-pi, pi]

// The scan as ND reads it: per beam its angle, whether something was seen, and the clearance from
// the hull (nothing seen: as if at range_max, so that a return just short of range_max is no gap).
struct Diagram {
  size_t n = 0;
  bool circular = false;
  std::vector<double> angle, clear;
  std::vector<uint8_t> hit;
  std::vector<Eigen::Vector2d> point;
};

Diagram diagram(const PolarScan& scan, const RectHull& hull) {
  Diagram d;
  d.n = scan.size();
  d.circular = scan.fullCircle();
  for (size_t i = 0; i < d.n; ++i) {
    const double a = scan.angle(i), r = scan.hit(i) ? scan.range(i) : scan.range_max;
    d.angle.push_back(a);
    d.hit.push_back(scan.hit(i));
    d.clear.push_back(hull.clearance(a, r));
    d.point.push_back(r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return d;
}

// One end of a region: a discontinuity (with the beam just outside) or the scan's edge.
struct End {
  bool disc = false, rising = false;  // rising: the beam outside is an obstacle nearer than the region
  size_t outside = 0;
};
// Beams start, start + 1, ..., start + len - 1 (mod n); lo is the end at start, hi the other.
struct Region {
  size_t start = 0, len = 0;
  End lo, hi;
  size_t at(size_t k, size_t n) const { return (start + k) % n; }
};

std::vector<Region> regions(const Diagram& d, double width) {
  std::vector<size_t> cuts;  // i: a discontinuity between beam i and the next
  for (size_t i = 0; i < (d.circular ? d.n : d.n - 1); ++i)
    if (std::abs(d.clear[i] - d.clear[(i + 1) % d.n]) > width) cuts.push_back(i);
  if (cuts.empty()) return {Region{0, d.n, {}, {}}};
  auto end = [&](size_t inside, size_t outside) {
    return End{true, d.hit[outside] && d.clear[outside] < d.clear[inside], outside};
  };
  std::vector<Region> out;
  if (d.circular) {
    for (size_t c = 0; c < cuts.size(); ++c) {
      const size_t s = (cuts[c] + 1) % d.n, last = cuts[(c + 1) % cuts.size()];
      out.push_back({s, (last + d.n - s) % d.n + 1, end(s, (s + d.n - 1) % d.n), end(last, (last + 1) % d.n)});
    }
  } else {
    size_t s = 0;
    for (size_t c = 0; c <= cuts.size(); ++c) {
      const size_t last = c < cuts.size() ? cuts[c] : d.n - 1;
      Region r{s, last - s + 1, {}, {}};
      if (s > 0) r.lo = end(s, s - 1);
      if (c < cuts.size()) r.hi = end(last, last + 1);
      out.push_back(r);
      s = last + 1;
    }
  }
  return out;
}

// The gap at a rising end: from its edge point to the nearest obstacle point across the valley,
// looking at most half a turn into it (further points lie on the robot's other side: for a post
// in open space, the post's far edge is not across the valley around it).
double gapWidth(const Diagram& d, const Region& r, bool lo, double increment) {
  const End& e = lo ? r.lo : r.hi;
  const End& other = lo ? r.hi : r.lo;
  const Eigen::Vector2d& edge = d.point[e.outside];
  double best = kInf;
  auto consider = [&](size_t i) {
    if (i != e.outside && d.hit[i]) best = std::min(best, (d.point[i] - edge).norm());
  };
  const size_t reach = std::min(r.len, size_t(std::floor(kPi / increment)));
  for (size_t k = 0; k < reach; ++k) consider(r.at(lo ? k : r.len - 1 - k, d.n));
  if (other.disc && double(r.len + 1) * increment <= kPi) consider(other.outside);
  return best;
}

// Whether the hull, driving straight at the goal, meets nothing the scan saw.
bool straightPathClear(const Diagram& d, const Eigen::Vector2d& goal, double half_width) {
  const double dist = goal.norm();
  const Eigen::Vector2d u = goal / dist;
  for (size_t i = 0; i < d.n; ++i) {
    if (!d.hit[i]) continue;
    const Eigen::Vector2d& p = d.point[i];
    const double along = p.dot(u), lateral = std::abs(u.x() * p.y() - u.y() * p.x());
    if (along >= 0 && along <= dist && lateral < half_width) return false;
  }
  return true;
}

// The free walking area: the navigable valley closest to the goal.
struct Choice {
  const Region* region = nullptr;
  bool goal_inside = false;
  bool rd_lo = true;  // the rising discontinuity closest to the goal is the lo end
  double distance = kInf;
};

Choice chooseValley(const Diagram& d, const std::vector<Region>& rs, std::optional<size_t> goal_beam,
                    double goal_angle, double width, double increment) {
  Choice best;
  for (const Region& r : rs) {
    const bool whole = !r.lo.disc && !r.hi.disc;  // no discontinuity anywhere
    const bool lo_ok = r.lo.rising && gapWidth(d, r, true, increment) >= width;
    const bool hi_ok = r.hi.rising && gapWidth(d, r, false, increment) >= width;
    if (!whole && !lo_ok && !hi_ok) continue;
    Choice c{&r, whole || (goal_beam && (*goal_beam + d.n - r.start) % d.n < r.len), true, 0.0};
    const double to_lo = std::abs(wrap(d.angle[r.start] - goal_angle));
    const double to_hi = std::abs(wrap(d.angle[r.at(r.len - 1, d.n)] - goal_angle));
    c.rd_lo = lo_ok && (!hi_ok || to_lo <= to_hi);
    if (!c.goal_inside) c.distance = c.rd_lo ? to_lo : to_hi;
    if (c.distance < best.distance) best = c;
  }
  return best;
}

void validate(const Eigen::Vector2d& goal, const NdConfig& c) {
  std::ostringstream s;
  if (!goal.allFinite()) s << "goal_in_base is not finite: (" << goal.x() << ", " << goal.y() << ")";
  else if (!(c.safety_distance > 0) || !std::isfinite(c.safety_distance))
    s << "NdConfig: safety_distance must be finite and > 0, got " << c.safety_distance;
  else if (!(c.wide_valley_deg > 0 && c.wide_valley_deg <= 360))
    s << "NdConfig: wide_valley_deg must be in (0, 360], got " << c.wide_valley_deg;
  if (!s.str().empty()) throw std::invalid_argument("nearnessDiagram: " + s.str());
}

NdCommand finish(const LocalCommand& c, NdSituation s) {
  NdCommand out;
  static_cast<LocalCommand&>(out) = c;
  out.situation = s;
  out.blocked = s == NdSituation::Blocked;
  return out;
}

}  // namespace

const char* situationName(NdSituation s) {
  switch (s) {
    case NdSituation::HSGR: return "HSGR";
    case NdSituation::HSWR: return "HSWR";
    case NdSituation::HSNR: return "HSNR";
    case NdSituation::LS1: return "LS1";
    case NdSituation::LS2: return "LS2";
    case NdSituation::Blocked: return "Blocked";
  }
  return "unknown";
}

NdCommand nearnessDiagram(const PolarScan& scan, const Eigen::Vector2d& goal, const RectHull& hull,
                          const NdConfig& config, const NdLimits& limits) {
  validate(goal, config);
  scan.validate("nearnessDiagram");
  hull.validate();
  limits.validate("nearnessDiagram");
  const double ds = config.safety_distance, width = hull.width();
  const Diagram d = diagram(scan, hull);
  double min_clear = kInf;
  for (size_t i = 0; i < d.n; ++i)
    if (d.hit[i]) min_clear = std::min(min_clear, std::max(0.0, d.clear[i]));
  const double goal_angle = std::atan2(goal.y(), goal.x());
  auto done = [&](const LocalCommand& c, NdSituation s) {
    NdCommand out = finish(c, s);
    out.min_clearance = min_clear;
    return out;
  };
  if (goal.norm() == 0) return done(steer(0, 0, limits), NdSituation::HSGR);  // there already

  // The free walking area and the high-safety direction theta_t.
  const std::vector<Region> rs = regions(d, width);
  NdSituation hs = NdSituation::HSGR;
  double target = goal_angle;
  if (!straightPathClear(d, goal, width / 2)) {
    const Choice c = chooseValley(d, rs, scan.indexOf(goal_angle), goal_angle, width, scan.angle_increment);
    if (!c.region) {
      LocalCommand stop = steer(goal_angle, 0, limits);
      stop.w = 0;
      return done(stop, NdSituation::Blocked);
    }
    const Region& r = *c.region;
    const double valley = double(r.len) * scan.angle_increment;
    if (c.goal_inside) {
      hs = NdSituation::HSGR;
    } else if (valley > config.wide_valley_deg * kPi / 180) {
      hs = NdSituation::HSWR;
      const double half = config.wide_valley_deg * kPi / 360;
      target = c.rd_lo ? d.angle[r.start] + half : d.angle[r.at(r.len - 1, d.n)] - half;
    } else {
      hs = NdSituation::HSNR;
      target = d.angle[r.start] + double(r.len - 1) * scan.angle_increment / 2;
    }
  }

  // Safety: the closest obstacle within the security zone on each side of theta_t.
  struct Near {
    double clear = kInf, angle = 0;
  } left, right;
  for (size_t i = 0; i < d.n; ++i) {
    if (!d.hit[i] || d.clear[i] >= ds) continue;
    Near& side = wrap(d.angle[i] - target) >= 0 ? left : right;
    if (d.clear[i] < side.clear) side = {std::max(0.0, d.clear[i]), d.angle[i]};
  }
  const bool l = left.clear < kInf, r = right.clear < kInf;
  if (!l && !r) return done(steer(target, 1.0, limits), hs);
  const double scale = min_clear / ds;
  if (l && r) {  // LS2: between the two, centring
    const double bisector = target + (wrap(left.angle - target) + wrap(right.angle - target)) / 2;
    return done(steer(bisector + kPi / 4 * (left.clear - right.clear) / ds, scale, limits), NdSituation::LS2);
  }
  // LS1: turned away from the obstacle (clockwise from one on the left), the more the nearer.
  const Near& o = l ? left : right;
  const double alpha = std::abs(wrap(target - o.angle)), away = l ? -1.0 : 1.0;
  const double separation = alpha + (kPi - alpha) * (ds - o.clear) / ds;
  return done(steer(o.angle + away * separation, scale, limits), NdSituation::LS1);
}

}  // namespace polynav
