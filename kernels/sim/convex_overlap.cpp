#include <polyloc/sim/convex_overlap.hpp>

#include <Eigen/Geometry>  // cross()
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace polyloc {

namespace {

// Projections of a and b onto the axis are disjoint. Closed intervals: touching is not disjoint.
bool separatedOn(const Eigen::Vector3d& axis, const ConvexShape& a, const ConvexShape& b) {
  double amin = std::numeric_limits<double>::infinity(), amax = -amin, bmin = amin, bmax = -amin;
  for (const auto& v : a.vertices) {
    const double d = axis.dot(v);
    amin = std::min(amin, d), amax = std::max(amax, d);
  }
  for (const auto& v : b.vertices) {
    const double d = axis.dot(v);
    bmin = std::min(bmin, d), bmax = std::max(bmax, d);
  }
  return amax < bmin || bmax < amin;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

}  // namespace

ConvexShape ConvexShape::triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return {{a, b, c}, {(b - a).cross(c - a)}, {b - a, c - b, a - c}};
}

ConvexShape ConvexShape::box(const Eigen::Vector3d& centre, const Eigen::Matrix3d& rotation,
                             const Eigen::Vector3d& half) {
  ConvexShape s;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d sign(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    s.vertices.push_back(centre + rotation * sign.cwiseProduct(half));
  }
  for (int k = 0; k < 3; ++k) s.face_normals.push_back(rotation.col(k));
  s.edge_dirs = s.face_normals;  // a box's edges run along its face normals
  return s;
}

ConvexShape ConvexShape::prism(const std::vector<Eigen::Vector2d>& convex_polygon, double z0, double z1,
                               const Eigen::Vector2d& origin, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  ConvexShape out;
  out.face_normals.emplace_back(0, 0, 1);  // top and bottom
  out.edge_dirs.emplace_back(0, 0, 1);     // the vertical edges
  const size_t n = convex_polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = convex_polygon[i];
    const Eigen::Vector2d q(origin.x() + c * p.x() - s * p.y(), origin.y() + s * p.x() + c * p.y());
    out.vertices.emplace_back(q.x(), q.y(), z0);
    out.vertices.emplace_back(q.x(), q.y(), z1);
    const Eigen::Vector2d e = convex_polygon[(i + 1) % n] - p;
    const Eigen::Vector2d d(c * e.x() - s * e.y(), s * e.x() + c * e.y());
    out.edge_dirs.emplace_back(d.x(), d.y(), 0);
    out.face_normals.emplace_back(d.y(), -d.x(), 0);
  }
  return out;
}

bool overlap(const ConvexShape& a, const ConvexShape& b) {
  if (a.vertices.empty() || b.vertices.empty()) return false;
  for (const auto* s : {&a, &b})
    for (const auto& n : s->face_normals)
      if (n.squaredNorm() > 0 && separatedOn(n, a, b)) return false;
  for (const auto& ea : a.edge_dirs)
    for (const auto& eb : b.edge_dirs) {
      const Eigen::Vector3d axis = ea.cross(eb);
      // (Nearly) parallel edges give no axis of their own: the face normals cover that case.
      if (axis.squaredNorm() <= 1e-12 * ea.squaredNorm() * eb.squaredNorm()) continue;
      if (separatedOn(axis, a, b)) return false;
    }
  return true;
}

std::vector<std::vector<Eigen::Vector2d>> convexPieces(const std::vector<Eigen::Vector2d>& polygon) {
  std::vector<Eigen::Vector2d> p = polygon;
  double area = 0, scale = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    area += p[i].x() * p[(i + 1) % p.size()].y() - p[(i + 1) % p.size()].x() * p[i].y();
    scale = std::max(scale, p[i].cwiseAbs().maxCoeff());
  }
  const double eps = 1e-12 * scale * scale;
  if (p.size() < 3 || !(std::abs(area) > eps)) throw std::invalid_argument("footprint polygon has no area");
  if (area < 0) std::reverse(p.begin(), p.end());  // counter-clockwise from here on
  const size_t n = p.size();
  bool convex = true;
  for (size_t i = 0; i < n; ++i) convex = convex && cross2(p[i], p[(i + 1) % n], p[(i + 2) % n]) >= -eps;
  if (convex) return {p};

  std::vector<std::vector<Eigen::Vector2d>> out;
  std::vector<size_t> idx(n);
  std::iota(idx.begin(), idx.end(), size_t{0});
  while (idx.size() > 3) {
    bool clipped = false;
    for (size_t i = 0; i < idx.size() && !clipped; ++i) {
      const size_t a = idx[(i + idx.size() - 1) % idx.size()], b = idx[i], c = idx[(i + 1) % idx.size()];
      const double turn = cross2(p[a], p[b], p[c]);
      if (turn < -eps) continue;  // reflex corner: not an ear
      if (turn > eps) {           // a collinear corner is dropped without a triangle
        bool empty = true;
        for (size_t j : idx)
          if (j != a && j != b && j != c && cross2(p[a], p[b], p[j]) >= -eps && cross2(p[b], p[c], p[j]) >= -eps &&
              cross2(p[c], p[a], p[j]) >= -eps)
            empty = false;
        if (!empty) continue;
        out.push_back({p[a], p[b], p[c]});
      }
      idx.erase(idx.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) throw std::invalid_argument("footprint polygon is not simple (no ear to clip)");
  }
  if (cross2(p[idx[0]], p[idx[1]], p[idx[2]]) > eps) out.push_back({p[idx[0]], p[idx[1]], p[idx[2]]});
  return out;
}

}  // namespace polyloc
