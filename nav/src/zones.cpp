// Zones: the queries, door passages and approach poses, validation, and the danger zones and door
// openings rasterised into a NavGrid. Reading a zone file is zones_yaml.cpp.
#include <polynav/zones.hpp>

#include "zones_detail.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace polynav {

using namespace zones_detail;

namespace {

[[noreturn]] void invalid(const std::string& what) { throw std::invalid_argument(what); }

// The door's opening (width x wall) and region (width x 2 depth) as rectangles.
Polygon doorRect(const Door& d, double half_across) {
  const Vector2d a = d.along * (d.width / 2), n = d.normal() * half_across;
  return {d.centre - a - n, d.centre + a - n, d.centre + a + n, d.centre - a + n};
}

// Cells whose centre lies inside or within half a cell of `poly`.
template <class F>
void forCellsNear(const NavGrid& g, const Polygon& poly, F&& f) {
  if (poly.empty() || g.size() == 0) return;
  const double half = g.resolution / 2, tol = half * (1 + 1e-9);
  const Box b = bounds(poly);
  auto range = [&](double lo, double hi, double origin, size_t n, size_t& i0, size_t& i1) {
    const double f0 = std::floor((lo - half - origin) / g.resolution - 0.5);
    const double f1 = std::ceil((hi + half - origin) / g.resolution - 0.5);
    if (!(f1 >= 0) || !(f0 <= double(n) - 1)) return false;  // also rejects NaN
    i0 = size_t(std::max(f0, 0.0));
    i1 = size_t(std::min(f1, double(n) - 1));
    return true;
  };
  size_t x0, x1, y0, y1;
  if (!range(b.lo.x(), b.hi.x(), g.origin_x, g.width, x0, x1) || !range(b.lo.y(), b.hi.y(), g.origin_y, g.height, y0, y1))
    return;
  for (size_t iy = y0; iy <= y1; ++iy)
    for (size_t ix = x0; ix <= x1; ++ix)
      if (polygonDistance(poly, g.centre(ix, iy)) <= tol) f(g.index(ix, iy));
}

}  // namespace

// ---------------------------------------------------------------------------------------- zones

bool Door::contains(const Vector2d& p) const {
  if (closed || !finite(p)) return false;
  const Vector2d d = p - centre;
  return std::abs(d.dot(along)) <= width / 2 && std::abs(d.dot(normal())) <= depth;
}

std::string Zones::roomAt(const Vector2d& p) const {
  for (const Room& r : rooms)
    if (pointInPolygon(r.polygon, p)) return r.name;
  return "";
}

std::optional<size_t> Zones::doorAt(const Vector2d& p) const {
  for (size_t i = 0; i < doors.size(); ++i)
    if (doors[i].contains(p)) return i;
  return std::nullopt;
}

std::optional<size_t> Zones::corridorAt(const Vector2d& p) const {
  for (size_t i = 0; i < corridors.size(); ++i)
    if (pointInPolygon(corridors[i].polygon, p)) return i;
  return std::nullopt;
}

bool Zones::inDanger(const Vector2d& p) const {
  if (!finite(p)) invalid("Zones::inDanger: point " + pt(p) + " is not finite");
  for (const DangerZone& z : danger)
    if (pointInPolygon(z.polygon, p)) return true;
  return false;
}

bool Zones::inDanger(const Polygon& footprint, const Vector3d& pose) const {
  if (footprint.size() < 3)
    invalid("Zones::inDanger: the footprint has " + std::to_string(footprint.size()) + " points, needs at least 3");
  for (size_t i = 0; i < footprint.size(); ++i)
    if (!finite(footprint[i])) invalid("Zones::inDanger: footprint point " + std::to_string(i) + " is not finite");
  if (!finite(pose))
    invalid("Zones::inDanger: pose (" + num(pose.x()) + ", " + num(pose.y()) + ", " + num(pose.z()) + ") is not finite");
  const Polygon placed = placeFootprint(footprint, pose);
  for (const DangerZone& z : danger)
    if (polygonsOverlap(placed, z.polygon)) return true;
  return false;
}

double Zones::dangerDistance(const Vector2d& p) const {
  if (!finite(p)) invalid("Zones::dangerDistance: point " + pt(p) + " is not finite");
  double d = std::numeric_limits<double>::infinity();
  for (const DangerZone& z : danger) d = std::min(d, polygonDistance(z.polygon, p));
  return d;
}

std::optional<size_t> Zones::doorIndex(const std::string& name) const {
  for (size_t i = 0; i < doors.size(); ++i)
    if (doors[i].name == name) return i;
  return std::nullopt;
}

std::optional<size_t> Zones::goalIndex(const std::string& name) const {
  for (size_t i = 0; i < goals.size(); ++i)
    if (goals[i].name == name) return i;
  return std::nullopt;
}

namespace {

// What is wrong with one entry ("" if nothing), for validate() and the loader's final check.
std::string doorProblem(const Door& d) {
  if (!finite(d.centre)) return "centre " + pt(d.centre) + " is not finite";
  if (!finite(d.along) || std::abs(d.along.norm() - 1) > 1e-9) return "along " + pt(d.along) + " must be a unit vector";
  if (!(d.width > 0) || !std::isfinite(d.width)) return "width must be > 0 and finite, got " + num(d.width);
  if (!(d.depth > 0) || !std::isfinite(d.depth)) return "depth must be > 0 and finite, got " + num(d.depth);
  if (!(d.wall >= 0) || !std::isfinite(d.wall)) return "wall must be >= 0 and finite, got " + num(d.wall);
  return "";
}

}  // namespace

std::string zones_detail::num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// As "(" + num(x) + ", " + num(y) + ")", written with a stream: that concatenation, compiled out of
// line, trips GCC 12's false -Wrestrict warning.
std::string zones_detail::pt(const Vector2d& p) {
  std::ostringstream s;
  s << '(' << p.x() << ", " << p.y() << ')';
  return s.str();
}

std::string zones_detail::goalProblem(const Zones& z, const GoalSpot& g) {
  const Vector2d p = g.pose.head<2>(), a = approachPose(g).head<2>();
  // Within the rooms' and corridors' box grown by 10 m (the margin geometry/domain.hpp gives the
  // map box): a goal at 1e300 m is a typo, not a place a plan could reach.
  Eigen::AlignedBox2d extent;
  for (const Room& r : z.rooms)
    for (const Vector2d& q : r.polygon) extent.extend(q);
  for (const Corridor& c : z.corridors)
    for (const Vector2d& q : c.polygon) extent.extend(q);
  constexpr double kMargin = 10.0;
  if (!extent.isEmpty() && (p.array() < extent.min().array() - kMargin || p.array() > extent.max().array() + kMargin).any())
    return "the goal " + pt(p) + " lies more than 10 m outside the rooms and corridors";
  for (const DangerZone& d : z.danger) {
    if (pointInPolygon(d.polygon, p)) return "the goal " + pt(p) + " lies in danger zone '" + d.name + "'";
    if (pointInPolygon(d.polygon, a)) return "the approach pose " + pt(a) + " lies in danger zone '" + d.name + "'";
  }
  return "";
}

void Zones::validate() const {
  auto check = [](const std::string& section, size_t i, const std::string& name, const std::string& problem) {
    if (!problem.empty())
      invalid("Zones: " + section + "[" + std::to_string(i) + "] '" + name + "': " + problem);
  };
  auto names = [&](const std::string& section, const auto& list) {
    std::map<std::string, size_t> seen;
    for (size_t i = 0; i < list.size(); ++i) {
      check(section, i, list[i].name, list[i].name.empty() ? "the name is empty" : "");
      auto [it, fresh] = seen.emplace(list[i].name, i);
      check(section, i, list[i].name, fresh ? "" : "duplicate name (also " + section + "[" + std::to_string(it->second) + "])");
    }
  };
  names("rooms", rooms), names("doors", doors), names("corridors", corridors), names("danger", danger),
      names("goals", goals);
  for (size_t i = 0; i < rooms.size(); ++i) {
    const std::string p = polygonProblem(rooms[i].polygon);
    check("rooms", i, rooms[i].name, p.empty() ? "" : "polygon " + p);
  }
  for (size_t i = 0; i < doors.size(); ++i) check("doors", i, doors[i].name, doorProblem(doors[i]));
  for (size_t i = 0; i < corridors.size(); ++i) {
    const Corridor& c = corridors[i];
    const std::string p = polygonProblem(c.polygon);
    check("corridors", i, c.name, p.empty() ? "" : "polygon " + p);
    check("corridors", i, c.name,
          finite(c.axis) && std::abs(c.axis.norm() - 1) <= 1e-9 ? "" : "axis " + pt(c.axis) + " must be a unit vector");
  }
  for (size_t i = 0; i < danger.size(); ++i) {
    const std::string p = polygonProblem(danger[i].polygon);
    check("danger", i, danger[i].name, p.empty() ? "" : "polygon " + p);
  }
  for (size_t i = 0; i < goals.size(); ++i) {
    const GoalSpot& g = goals[i];
    check("goals", i, g.name, finite(g.pose) ? "" : "pose is not finite");
    check("goals", i, g.name,
          g.approach >= 0 && g.approach <= kMaxApproach ? "" : "approach must be in [0, 10] m, got " + num(g.approach));
    check("goals", i, g.name, goalProblem(*this, g));
  }
}

DoorPassage doorPassage(const Door& door, const Vector2d& from_side_point) {
  if (door.closed) invalid("doorPassage: door '" + door.name + "' is closed");
  if (const std::string p = doorProblem(door); !p.empty()) invalid("doorPassage: door '" + door.name + "': " + p);
  if (!finite(from_side_point)) invalid("doorPassage: point " + pt(from_side_point) + " is not finite");
  const Vector2d n = door.normal();
  const double side = (from_side_point - door.centre).dot(n) >= 0 ? 1.0 : -1.0;
  const Vector2d heading = -side * n;  // through the door, away from the side we come from
  const double yaw = std::atan2(heading.y(), heading.x());
  DoorPassage out;
  const Vector2d before = door.centre - heading * door.depth, after = door.centre + heading * door.depth;
  out.before = {before.x(), before.y(), yaw};
  out.after = {after.x(), after.y(), yaw};
  return out;
}

std::vector<GoalSpot> randomGoals(const Zones& zones, size_t n, uint64_t seed) {
  if (zones.goals.size() < 2) throw ZonesError("random missions need at least 2 goals, the zones have " + std::to_string(zones.goals.size()));
  std::vector<GoalSpot> out;
  std::mt19937_64 rng(seed);
  size_t last = zones.goals.size();
  for (size_t k = 0; k < n; ++k) {
    size_t i;
    do i = size_t(rng() % zones.goals.size());
    while (i == last);
    out.push_back(zones.goals[i]);
    last = i;
  }
  return out;
}

Vector3d approachPose(const GoalSpot& goal) {
  const double yaw = goal.pose.z();
  return {goal.pose.x() - goal.approach * std::cos(yaw), goal.pose.y() - goal.approach * std::sin(yaw), yaw};
}

// --------------------------------------------------------------------------------------- raster

void markDanger(const Zones& zones, NavGrid& g) {
  g.validate();
  for (const DangerZone& z : zones.danger) forCellsNear(g, z.polygon, [&](size_t i) { g.occupied[i] = 1; });
}

void markDoors(const Zones& zones, NavGrid& g) {
  g.validate();
  if (g.door.empty()) g.door.assign(g.size(), 0);
  for (const Door& d : zones.doors) {
    const Polygon opening = doorRect(d, d.wall / 2);
    if (d.closed)
      forCellsNear(g, opening, [&](size_t i) { g.occupied[i] = 1; });
    else
      forCellsNear(g, opening, [&](size_t i) { g.door[i] = 1; });
  }
}

}  // namespace polynav
