// Solid-leaf BSP backend (the thesis's map representation): split planes are the planes of the
// map's polygons, every leaf is empty or solid, rays walk the tree front to back and stop at the
// first solid leaf. Needs closed, outward-facing solids; the constructor says when a map is not.
//
// Build: (1) the map is checked (each edge used by exactly two triangles in opposite directions,
// each connected solid with positive volume); (2) faces inside other solids and touching face
// pairs are clipped away (a union of the solids, so that only the boundary of the solid region
// remains: a solid-leaf tree of overlapping solids would call their inside empty); (3) the tree
// is built without recursion, each node's plane chosen among its polygons' planes (coplanar
// polygons merged into one candidate) by the lowest k * splits + (1 - k) * |front - back|.
//
// What a hit fills: range (to the plane where the ray enters solid), normal (that plane's, facing
// the ray), triangle and label (the map triangle on that plane that holds the hit point, or the
// nearest one on it). Nothing is allocated per call; the batch loops and the arena are
// PerRayCaster's.
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/per_ray_caster.hpp>

#include <memory>

namespace polyloc {

struct BspOptions {
  int threads = 0;          // 0 = all cores
  float k = 0.8f;           // score weight: k * splits + (1 - k) * imbalance (the thesis's k)
  size_t max_candidates = 0;  // planes scored per node; 0 = all (>0: evenly spaced sample, faster
                              // builds on big maps, a few % more nodes)
  int max_depth = 1000;     // build fails beyond this depth (traversal stack size)
  double plane_eps = 1e-5;  // m: a vertex this close to a plane is on it
};

// What the build produced, for benchmarks and `polyloc bench bsp`.
struct BspStats {
  size_t input_triangles = 0;
  size_t boundary_polygons = 0;  // after clipping away faces inside other solids
  size_t split_polygons = 0;     // polygons cut in two by a split plane during the build
  size_t nodes = 0;              // interior nodes; leaves are encoded in the child links
  size_t empty_leaves = 0, solid_leaves = 0;
  int depth = 0;                 // longest root-to-leaf path (interior nodes)
  size_t node_bytes = 0;         // nodes (32 bytes each, plane + children + triangle range)
  size_t triangle_ref_bytes = 0;  // per-node lists of map triangles, for hit triangle/label
  double build_s = 0;
  double memoryMb() const { return double(node_bytes + triangle_ref_bytes) / (1024.0 * 1024.0); }
};

class BspCaster final : public PerRayCaster {
 public:
  // Throws MapError naming mesh.source and the problem when the map is not closed and outward.
  explicit BspCaster(const Mesh& mesh, const BspOptions& options = {});
  ~BspCaster() override;
  BspCaster(const BspCaster&) = delete;
  BspCaster& operator=(const BspCaster&) = delete;

  const char* name() const override { return "bsp"; }
  // Point descent; with clearance r a node's both sides are visited when the point is within r
  // of its plane, so a point is free only if no solid leaf is reachable by its r-ball. Planes are
  // tested one at a time, so near convex corners the margin is conservative (up to r * sqrt(3)).
  void queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                 uint8_t* free) const override;

  const BspStats& stats() const;
  size_t memoryBytes() const override { return stats().node_bytes + stats().triangle_ref_bytes; }

 private:
  void traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t0,
                float t1, const CastOptions& opt) const override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace polyloc
