// Polygon primitives of the BSP build, in double precision: side of a plane, cutting a convex
// polygon in two, and the set of distinct triangle planes (coplanar triangles merged).
#include "bsp_tree.hpp"

#include <cmath>

namespace polyloc::bsp {

Side classify(const Polygon& poly, const Plane& plane, double eps) {
  int front = 0, back = 0;
  for (const Eigen::Vector3d& p : poly.v) {
    const double s = plane.dist(p);
    front += s > eps;
    back += s < -eps;
  }
  if (front && back) return kSpanning;
  return front ? kFront : back ? kBack : kOn;
}

void split(const Polygon& poly, const Plane& plane, double eps, Polygon& front, Polygon& back) {
  front.v.clear();
  back.v.clear();
  front.tri = back.tri = poly.tri;
  front.plane = back.plane = poly.plane;
  front.reversed = back.reversed = poly.reversed;
  const size_t n = poly.v.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = poly.v[i];
    const Eigen::Vector3d& b = poly.v[(i + 1) % n];
    const double sa = plane.dist(a), sb = plane.dist(b);
    const int ca = sa > eps ? 1 : sa < -eps ? -1 : 0;
    const int cb = sb > eps ? 1 : sb < -eps ? -1 : 0;
    if (ca >= 0) front.v.push_back(a);
    if (ca <= 0) back.v.push_back(a);
    if (ca * cb < 0) {  // the edge crosses the plane: both halves get the crossing point
      const Eigen::Vector3d x = a + (b - a) * (sa / (sa - sb));
      front.v.push_back(x);
      back.v.push_back(x);
    }
  }
  if (front.v.size() < 3) front.v.clear();
  if (back.v.size() < 3) back.v.clear();
}

Plane trianglePlane(const Mesh& mesh, uint32_t tri) {
  const Triangle& t = mesh.triangles[tri];
  const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
  const Eigen::Vector3d b = mesh.vertices[t[1]].cast<double>();
  const Eigen::Vector3d c = mesh.vertices[t[2]].cast<double>();
  Plane p;
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  p.n = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  p.d = p.n.dot((a + b + c) / 3.0);
  return p;
}

uint32_t PlaneSet::add(const Plane& oriented, bool& reversed) {
  // Canonical orientation: the largest normal component positive.
  int axis = 0;
  oriented.n.cwiseAbs().maxCoeff(&axis);
  reversed = oriented.n[axis] < 0;
  Plane p = oriented;
  if (reversed) {
    p.n = -p.n;
    p.d = -p.d;
  }
  // Quantised key (1e-6 in n, 1e-5 m in d); a plane straddling a cell boundary stays two
  // entries, which costs one more candidate, not correctness (sides are decided by distance).
  const auto q = [](double x, double s) { return static_cast<int64_t>(std::llround(x * s)); };
  uint64_t key = 1469598103934665603ull;
  for (int64_t v : {q(p.n.x(), 1e6), q(p.n.y(), 1e6), q(p.n.z(), 1e6), q(p.d, 1e5)})
    key = (key ^ static_cast<uint64_t>(v)) * 1099511628211ull;
  const auto [it, inserted] = index_.try_emplace(key, static_cast<uint32_t>(planes_.size()));
  if (inserted) planes_.push_back(p);
  return it->second;
}

Plane PlaneSet::oriented(uint32_t i, bool reversed) const {
  Plane p = planes_[i];
  if (reversed) {
    p.n = -p.n;
    p.d = -p.d;
  }
  return p;
}

}  // namespace polyloc::bsp
