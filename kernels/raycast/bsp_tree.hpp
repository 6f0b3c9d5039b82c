// Internals of the BSP backend: polygons in double precision for the build, the compact float
// tree the queries walk, and the three build steps (check, union of solids, tree).
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/raycast/bsp.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace polyloc::bsp {

struct Plane {
  Eigen::Vector3d n{0, 0, 1};  // unit normal; front side is where dist > 0
  double d = 0;                // n . x = d on the plane
  double dist(const Eigen::Vector3d& p) const { return n.dot(p) - d; }
};

// Child links: >= 0 is a node index, below 0 a leaf.
inline constexpr int32_t kEmpty = -1;
inline constexpr int32_t kSolid = -2;

// A convex polygon fragment of one map triangle, counter-clockwise seen from its front.
struct Polygon {
  std::vector<Eigen::Vector3d> v;
  uint32_t tri = 0;    // source triangle in the Mesh
  uint32_t plane = 0;     // index of its (unoriented) plane in the build's plane list
  bool reversed = false;  // faces against planes[plane].n
};

// Unoriented planes of the map's triangles; coplanar triangles share one entry.
class PlaneSet {
 public:
  // Index of the triangle plane (merged with a stored one when within ~1e-6 in n and d);
  // `reversed` tells whether the input faces against the stored normal.
  uint32_t add(const Plane& oriented, bool& reversed);
  const Plane& operator[](size_t i) const { return planes_[i]; }
  size_t size() const { return planes_.size(); }
  Plane oriented(uint32_t i, bool reversed) const;

 private:
  std::vector<Plane> planes_;
  std::unordered_map<uint64_t, uint32_t> index_;
};

// Build-time node: plane by index (double precision), children as in Node.
struct BuildNode {
  uint32_t plane = 0;
  bool reversed = false;
  int32_t child[2] = {kEmpty, kSolid};
  std::vector<uint32_t> tris;  // map triangles with a polygon on this plane
};

enum Side : int { kOn = 0, kFront = 1, kBack = 2, kSpanning = 3 };
Side classify(const Polygon& poly, const Plane& plane, double eps);
// Cuts a spanning polygon in two (either output may be left empty for an on-plane sliver).
void split(const Polygon& poly, const Plane& plane, double eps, Polygon& front, Polygon& back);
// The triangle's own plane (orientation from its winding).
Plane trianglePlane(const Mesh& mesh, uint32_t tri);

struct Node {  // 32 bytes
  float nx, ny, nz, d;    // split plane, front = outside of the polygons that chose it
  int32_t child[2];       // [0] front, [1] back
  uint32_t tri_first;     // map triangles lying on this plane: Tree::tris[first, first + count)
  uint32_t tri_count;
};
static_assert(sizeof(Node) == 32);

struct Tree {
  std::vector<Node> nodes;
  std::vector<uint32_t> tris;
  int32_t root = kEmpty;
};

// Connected solid of each triangle (triangles sharing a vertex index); `count` solids.
std::vector<uint32_t> solidOfTriangle(const Mesh& mesh, uint32_t& count);
// (1) Throws MapError unless every edge is shared by two triangles in opposite directions and
//     every connected solid encloses positive volume.
void checkClosedOutward(const Mesh& mesh);
// (2) The boundary of the union of the map's solids as convex polygons; fills `planes`.
std::vector<Polygon> unionBoundary(const Mesh& mesh, PlaneSet& planes, double eps);
// (3) The solid-leaf tree over polygons (front of every node empty, back solid where no polygon
//     is left); root is nodes[0] unless the result is one leaf (then `root` says which).
std::vector<BuildNode> buildNodes(std::vector<Polygon> polys, const PlaneSet& planes,
                                  const BspOptions& options, BspStats& stats, int32_t& root);
// The compact float tree the queries walk.
Tree compact(const std::vector<BuildNode>& nodes, int32_t root, const PlaneSet& planes);

}  // namespace polyloc::bsp
