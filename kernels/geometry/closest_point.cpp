#include <polyloc/geometry/closest_point.hpp>

namespace polyloc {
namespace {

// Voronoi-region walk: vertex regions, then edge regions, else the face interior.
template <class S>
Eigen::Matrix<S, 3, 1> closest(const Eigen::Matrix<S, 3, 1>& p, const Eigen::Matrix<S, 3, 1>& a,
                               const Eigen::Matrix<S, 3, 1>& b, const Eigen::Matrix<S, 3, 1>& c) {
  using V = Eigen::Matrix<S, 3, 1>;
  const V ab = b - a, ac = c - a, ap = p - a;
  const S d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= S(0) && d2 <= S(0)) return a;
  const V bp = p - b;
  const S d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= S(0) && d4 <= d3) return b;
  const S vc = d1 * d4 - d3 * d2;
  if (vc <= S(0) && d1 >= S(0) && d3 <= S(0)) return a + (d1 / (d1 - d3)) * ab;
  const V cp = p - c;
  const S d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= S(0) && d5 <= d6) return c;
  const S vb = d5 * d2 - d1 * d6;
  if (vb <= S(0) && d2 >= S(0) && d6 <= S(0)) return a + (d2 / (d2 - d6)) * ac;
  const S va = d3 * d6 - d5 * d4;
  if (va <= S(0) && (d4 - d3) >= S(0) && (d5 - d6) >= S(0))
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const S denom = S(1) / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

Eigen::Vector3f closestPointOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                                       const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
  return closest(p, a, b, c);
}

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return closest(p, a, b, c);
}

}  // namespace polyloc
