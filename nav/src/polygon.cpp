// The polygon tools of polygon.hpp.
#include <polynav/polygon.hpp>

#include "zones_detail.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

namespace polynav {

using namespace zones_detail;

namespace {

double cross(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Sign of the turn a -> b -> c: > 0 left, < 0 right, 0 collinear (exact in the doubles given).
int orient(const Vector2d& a, const Vector2d& b, const Vector2d& c) {
  const double v = cross(b - a, c - a);
  return (v > 0) - (v < 0);
}

// p, collinear with segment ab, lies within its bounding box.
bool withinBox(const Vector2d& a, const Vector2d& b, const Vector2d& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

bool onSegment(const Vector2d& a, const Vector2d& b, const Vector2d& p) {
  return orient(a, b, p) == 0 && withinBox(a, b, p);
}

// Closed segments share a point (crossing, touching or overlapping collinearly).
bool segmentsIntersect(const Vector2d& p1, const Vector2d& p2, const Vector2d& q1, const Vector2d& q2) {
  const int d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2), d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && withinBox(q1, q2, p1)) || (d2 == 0 && withinBox(q1, q2, p2)) ||
         (d3 == 0 && withinBox(p1, p2, q1)) || (d4 == 0 && withinBox(p1, p2, q2));
}

double segmentDistance(const Vector2d& a, const Vector2d& b, const Vector2d& p) {
  const Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace

bool pointInPolygon(const Polygon& poly, const Vector2d& p) {
  const size_t n = poly.size();
  if (n == 0 || !finite(p)) return false;
  int wn = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vector2d& a = poly[i];
    const Vector2d& b = poly[(i + 1) % n];
    if (onSegment(a, b, p)) return true;
    if (a.y() <= p.y()) {
      if (b.y() > p.y() && orient(a, b, p) > 0) ++wn;
    } else if (b.y() <= p.y() && orient(a, b, p) < 0) {
      --wn;
    }
  }
  return wn != 0;
}

double polygonDistance(const Polygon& poly, const Vector2d& p) {
  if (poly.empty()) return std::numeric_limits<double>::infinity();
  if (pointInPolygon(poly, p)) return 0.0;
  double d = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < poly.size(); ++i) d = std::min(d, segmentDistance(poly[i], poly[(i + 1) % poly.size()], p));
  return d;
}

bool polygonsOverlap(const Polygon& a, const Polygon& b) {
  if (a.empty() || b.empty()) return false;
  const Box ba = bounds(a), bb = bounds(b);
  if (ba.hi.x() < bb.lo.x() || bb.hi.x() < ba.lo.x() || ba.hi.y() < bb.lo.y() || bb.hi.y() < ba.lo.y()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j)
      if (segmentsIntersect(a[i], a[(i + 1) % a.size()], b[j], b[(j + 1) % b.size()])) return true;
  // No edges meet: one lies wholly inside the other, or they are apart.
  return pointInPolygon(b, a[0]) || pointInPolygon(a, b[0]);
}

Polygon placeFootprint(const Polygon& footprint, const Vector3d& pose) {
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  Polygon out;
  out.reserve(footprint.size());
  for (const Vector2d& q : footprint) out.emplace_back(pose.x() + c * q.x() - s * q.y(), pose.y() + s * q.x() + c * q.y());
  return out;
}

std::string polygonProblem(const Polygon& poly) {
  const size_t n = poly.size();
  if (n < 3) return "has " + std::to_string(n) + " point" + (n == 1 ? "" : "s") + ", needs at least 3";
  for (size_t i = 0; i < n; ++i)
    if (!finite(poly[i])) return "point " + std::to_string(i) + " is not finite";
  for (size_t i = 0; i < n; ++i)
    if (poly[i] == poly[(i + 1) % n])
      return "points " + std::to_string(i) + " and " + std::to_string((i + 1) % n) + " coincide";
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    const Vector2d e1 = poly[j] - poly[i], e2 = poly[(j + 1) % n] - poly[j];
    if (cross(e1, e2) == 0 && e1.dot(e2) < 0)
      return "edges " + std::to_string(i) + " and " + std::to_string(j) + " overlap (the outline turns back)";
  }
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segmentsIntersect(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]))
        return "edges " + std::to_string(i) + " and " + std::to_string(j) + " cross or touch (not a simple polygon)";
    }
  double area2 = 0;
  for (size_t i = 0; i < n; ++i) area2 += cross(poly[i], poly[(i + 1) % n]);
  if (std::abs(area2) / 2 < 1e-12) return "has no area";
  return "";
}

}  // namespace polynav
