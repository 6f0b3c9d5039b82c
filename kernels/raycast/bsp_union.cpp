// BSP build step 2: the boundary of the union of the map's solids. Maps are made of closed solids
// that touch or overlap (a wall standing on the floor slab, a table leg in the floor): their faces
// inside another solid are not boundary, and a solid-leaf tree built with them would call the
// inside of the other solid empty. Each solid gets a small BSP tree; every solid's polygons are
// clipped against the trees of the solids whose boxes overlap theirs, keeping what is outside.
// On a shared plane, faces of opposite direction (two solids touching) are both dropped; faces of
// the same direction are kept once (by the lower solid index).
#include "bsp_tree.hpp"

#include <Eigen/Geometry>

namespace polyloc::bsp {
namespace {

struct SolidTree {
  std::vector<BuildNode> nodes;
  int32_t root = kEmpty;
  Eigen::AlignedBox3d box;
};

Eigen::AlignedBox3d boxOf(const Polygon& p) {
  Eigen::AlignedBox3d b;
  for (const Eigen::Vector3d& v : p.v) b.extend(v);
  return b;
}

// Appends to `out` the parts of `poly` outside the solid (see the file comment for the plane
// shared with one of its faces: `keep_same` keeps a same-direction coplanar face).
void clipOutside(const SolidTree& s, const PlaneSet& planes, const Polygon& poly, bool keep_same,
                 double eps, std::vector<Polygon>& out, std::vector<std::pair<int32_t, Polygon>>& stack) {
  stack.clear();
  stack.emplace_back(s.root, poly);
  Polygon f, b;
  while (!stack.empty()) {
    auto [node_id, p] = std::move(stack.back());
    stack.pop_back();
    if (node_id == kEmpty) {
      out.push_back(std::move(p));
      continue;
    }
    if (node_id == kSolid) continue;
    const BuildNode& n = s.nodes[node_id];
    const Plane pl = planes.oriented(n.plane, n.reversed);
    Side side = p.plane == n.plane ? kOn : classify(p, pl, eps);
    if (side == kOn) {
      const Eigen::Vector3d pn = planes.oriented(p.plane, p.reversed).n;
      side = pn.dot(pl.n) > 0 && keep_same ? kFront : kBack;
    }
    if (side == kFront) {
      stack.emplace_back(n.child[0], std::move(p));
    } else if (side == kBack) {
      stack.emplace_back(n.child[1], std::move(p));
    } else {
      split(p, pl, eps, f, b);
      if (!f.v.empty()) stack.emplace_back(n.child[0], f);
      if (!b.v.empty()) stack.emplace_back(n.child[1], b);
    }
  }
}

}  // namespace

std::vector<Polygon> unionBoundary(const Mesh& mesh, PlaneSet& planes, double eps) {
  uint32_t count = 0;
  const std::vector<uint32_t> solid_of = solidOfTriangle(mesh, count);
  std::vector<std::vector<Polygon>> polys(count);
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const Plane pl = trianglePlane(mesh, t);
    if (pl.n.squaredNorm() == 0) continue;  // zero area: no surface
    Polygon p;
    p.tri = t;
    for (uint32_t v : mesh.triangles[t]) p.v.push_back(mesh.vertices[v].cast<double>());
    p.plane = planes.add(pl, p.reversed);
    polys[solid_of[t]].push_back(std::move(p));
  }
  // One tree per solid; picking the first plane is enough for the few faces of one solid.
  std::vector<SolidTree> trees(count);
  BspOptions quick;
  quick.max_candidates = 1;
  for (uint32_t s = 0; s < count; ++s) {
    BspStats ignored;
    trees[s].nodes = buildNodes(polys[s], planes, quick, ignored, trees[s].root);
    for (const Polygon& p : polys[s]) trees[s].box.extend(boxOf(p));
    trees[s].box.min().array() -= 2 * eps;
    trees[s].box.max().array() += 2 * eps;
  }
  std::vector<Polygon> result, next;
  std::vector<std::pair<int32_t, Polygon>> stack;
  for (uint32_t i = 0; i < count; ++i) {
    std::vector<Polygon> frags = polys[i];
    for (uint32_t j = 0; j < count && !frags.empty(); ++j) {
      if (j == i || !trees[i].box.intersects(trees[j].box)) continue;
      next.clear();
      for (const Polygon& p : frags) {
        if (!trees[j].box.intersects(boxOf(p)))
          next.push_back(p);
        else
          clipOutside(trees[j], planes, p, j > i, eps, next, stack);
      }
      frags.swap(next);
    }
    for (Polygon& p : frags) result.push_back(std::move(p));
  }
  return result;
}

}  // namespace polyloc::bsp
