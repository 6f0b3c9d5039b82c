// Internal to polynav_core, not a public header: the small helpers that polygon.cpp, zones.cpp and
// zones_yaml.cpp share, kept in one place rather than copied into each.
#pragma once

#include <polynav/polygon.hpp>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>

namespace polynav {

struct GoalSpot;
struct Zones;

// The three files open with `using namespace zones_detail;`: these helpers and the short Eigen names.
namespace zones_detail {

using Eigen::Vector2d;
using Eigen::Vector3d;

inline bool finite(const Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }
inline bool finite(const Vector3d& p) { return finite(Vector2d(p.x(), p.y())) && std::isfinite(p.z()); }

struct Box {
  Vector2d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vector2d hi = -lo;
};

inline Box bounds(const Polygon& poly) {
  Box b;
  for (const Vector2d& p : poly) b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
  return b;
}

// A number as `<<` writes it ("0.75", "nan"); a point as "(x, y)". For error messages (zones.cpp).
std::string num(double v);
std::string pt(const Vector2d& p);

// What is wrong with a goal's position ("" if nothing): the goal more than 10 m outside the rooms
// and corridors, or it or its approach pose in a danger zone. For Zones::validate and for the
// loader, which checks each goal as it reads it.
std::string goalProblem(const Zones& z, const GoalSpot& g);
constexpr double kMaxApproach = 10.0;  // m: GoalSpot::approach at most

}  // namespace zones_detail
}  // namespace polynav
