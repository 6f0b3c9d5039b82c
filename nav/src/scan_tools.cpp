#include <polynav/scan_tools.hpp>

#include <algorithm>
#include <cmath>

namespace polynav {

std::vector<Eigen::Vector2d> scanPoints(const PolarScan& scan, const Eigen::Vector3d& pose) {
  std::vector<Eigen::Vector2d> out;
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r > scan.range_max || r <= 0) continue;
    const double a = scan.angle(i), bx = r * std::cos(a), by = r * std::sin(a);
    out.emplace_back(pose.x() + c * bx - s * by, pose.y() + s * bx + c * by);
  }
  return out;
}

void addPolygons(PolarScan& scan, const std::vector<Polygon>& polygons, const Eigen::Vector3d& pose) {
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  for (const Polygon& poly : polygons) {
    // Edges in base_link.
    std::vector<Eigen::Vector2d> q;
    for (const auto& p : poly) {
      const Eigen::Vector2d d = p - pose.head<2>();
      q.emplace_back(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
    }
    for (size_t i = 0; i < scan.ranges.size(); ++i) {
      const double a = scan.angle(i);
      const Eigen::Vector2d u(std::cos(a), std::sin(a));
      for (size_t k = 0; k < q.size(); ++k) {
        const Eigen::Vector2d p0 = q[k], e = q[(k + 1) % q.size()] - p0;
        const double den = u.x() * e.y() - u.y() * e.x();
        if (std::abs(den) < 1e-12) continue;
        const double t = (p0.x() * e.y() - p0.y() * e.x()) / den;   // along the beam
        const double v = (p0.x() * u.y() - p0.y() * u.x()) / den;   // along the edge
        if (t > 0 && v >= 0 && v <= 1 && (!(scan.ranges[i] <= scan.range_max) || t < scan.ranges[i]))
          scan.ranges[i] = float(t);
      }
    }
  }
}

double freeTravel(const PolarScan& scan, const RectHull& hull, bool forward) {
  double best = INFINITY;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r > scan.range_max || r <= 0) continue;
    const double a = scan.angle(i), x = r * std::cos(a), y = r * std::sin(a);
    if (y > hull.left || y < -hull.right) continue;  // beside the hull: not in the way
    if (forward && x > 0) best = std::min(best, x - hull.front);
    if (!forward && x < 0) best = std::min(best, -x - hull.rear);
  }
  return std::max(0.0, best);
}

bool rotationClear(const PolarScan& scan, const RectHull& hull, double angle, double margin) {
  const double reach = std::hypot(std::max(hull.front, hull.rear), std::max(hull.left, hull.right)) + margin;
  const int steps = std::max(1, int(std::ceil(std::abs(angle) / 0.02)));
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r) || r > scan.range_max || r <= 0 || r > reach) continue;
    // Turned by phi, the robot sees the point at angle - phi.
    for (int k = 0; k <= steps; ++k)
      if (hull.extent(scan.angle(i) - angle * k / steps) + margin >= r) return false;
  }
  return true;
}

double obstructedAt(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& path,
                    size_t from_segment, double ahead_m, double radius, Eigen::Vector2d* where) {
  double s = 0;
  for (size_t i = from_segment; i + 1 < path.size() && s <= ahead_m; ++i) {
    const Eigen::Vector2d a = path[i], d = path[i + 1] - a;
    const double len2 = d.squaredNorm();
    for (const auto& p : points) {
      const double u = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
      if ((a + u * d - p).norm() < radius) {
        if (where) *where = p;
        return s + u * std::sqrt(len2);
      }
    }
    s += std::sqrt(len2);
  }
  return -1;
}

}  // namespace polynav
