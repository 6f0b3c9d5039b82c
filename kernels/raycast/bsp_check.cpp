// BSP build step 1: the map must be closed and outward-facing, else the leaves' solid/empty
// labels are meaningless. The message names the map, the problem and one place to look.
#include "bsp_tree.hpp"

#include <polyloc/map/load.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <numeric>

namespace polyloc::bsp {
namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

std::string at(const Eigen::Vector3f& p) {
  return fmt::format("({:.3f}, {:.3f}, {:.3f})", p.x(), p.y(), p.z());
}

}  // namespace

std::vector<uint32_t> solidOfTriangle(const Mesh& mesh, uint32_t& count) {
  std::vector<uint32_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const Triangle& t : mesh.triangles)
    for (int k = 1; k < 3; ++k) parent[findRoot(parent, t[k])] = findRoot(parent, t[0]);
  std::vector<uint32_t> id(mesh.vertices.size(), UINT32_MAX), out(mesh.triangles.size());
  count = 0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    uint32_t& r = id[findRoot(parent, mesh.triangles[i][0])];
    if (r == UINT32_MAX) r = count++;
    out[i] = r;
  }
  return out;
}

void checkClosedOutward(const Mesh& mesh) {
  const std::string name = mesh.source.empty() ? "map" : mesh.source;
  const std::string needs = "bsp needs closed, outward-facing solids";
  const size_t nv = mesh.vertices.size();
  // Directed edges sorted by their undirected key: a good edge is a pair (a, b), (b, a).
  struct Edge {
    uint64_t key;
    bool forward;
  };
  std::vector<Edge> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv)
      throw MapError(fmt::format("{}: triangle {} references a missing vertex; {}", name, i, needs));
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      edges.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
  size_t open = 0, non_manifold = 0, flipped = 0;
  Eigen::Vector3f open_at, nm_at, flip_at;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    int fwd = 0;
    while (j < edges.size() && edges[j].key == edges[i].key) fwd += edges[j++].forward;
    const Eigen::Vector3f mid = 0.5f * (mesh.vertices[edges[i].key >> 32] +
                                        mesh.vertices[edges[i].key & 0xFFFFFFFFu]);
    const size_t n = j - i;
    if (n == 1 && open++ == 0) open_at = mid;
    if (n > 2 && non_manifold++ == 0) nm_at = mid;
    if (n == 2 && fwd != 1 && flipped++ == 0) flip_at = mid;
    i = j;
  }
  if (open)
    throw MapError(fmt::format("{}: {} open edges, e.g. at {}; {}", name, open, at(open_at), needs));
  if (non_manifold)
    throw MapError(fmt::format("{}: {} edges shared by more than two triangles, e.g. at {}; {}",
                               name, non_manifold, at(nm_at), needs));
  if (flipped)
    throw MapError(fmt::format("{}: {} edges with inconsistent winding (flipped triangles), e.g. "
                               "at {}; {}", name, flipped, at(flip_at), needs));
  uint32_t count = 0;
  const std::vector<uint32_t> solid = solidOfTriangle(mesh, count);
  std::vector<double> volume(count, 0.0);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    volume[solid[i]] += mesh.vertices[t[0]].cast<double>().dot(
        mesh.vertices[t[1]].cast<double>().cross(mesh.vertices[t[2]].cast<double>())) / 6.0;
  }
  size_t inward = 0, first = 0;
  for (uint32_t s = 0; s < count; ++s)
    if (!(volume[s] > 0) && inward++ == 0) first = s;
  if (inward) {
    const size_t tri = std::find(solid.begin(), solid.end(), first) - solid.begin();
    throw MapError(fmt::format("{}: {} solids face inward or enclose no volume, e.g. at {}; {}", name,
                               inward, at(mesh.vertices[mesh.triangles[tri][0]]), needs));
  }
}

}  // namespace polyloc::bsp
