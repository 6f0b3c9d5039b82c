// Where triangles lie on a triangle facing the other way. Where two closed solids touch (a
// cabinet against a wall, furniture standing on the floor slab, the boxes of an extruded grid)
// their faces coincide: a ray from inside one meets its exit face and the neighbour's entry face
// at one distance, and which of the two a ray caster reports may depend on its traversal order
// (raycast/embree.cpp settles such ties).
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace polyloc {

// Distances and offsets this close are one: `at_least` m, or one float step at the mesh's
// largest coordinate, whichever is more (the casters' tie rule uses it too).
float coincidenceTolerance(const Mesh& mesh, float at_least = 1e-5f);

// Per triangle, the boxes where another triangle lies on it facing the other way: in its plane
// (normals opposite within about 1e-3, offsets within tolerance()) with extents overlapping
// with positive area. A floor under a table has the table legs' footprints, nothing elsewhere.
// The tolerance is `tolerance` m or a float step at the map's largest coordinate, whichever is
// more: a building in UTM coordinates (x = 5e5 m, floats 3 cm apart) keeps its ties.
class CoincidentFaces {
 public:
  CoincidentFaces() = default;
  explicit CoincidentFaces(const Mesh& mesh, float tolerance = 1e-5f);

  bool any() const { return !parts_.empty(); }
  bool has(uint32_t tri) const { return tri < has_.size() && has_[tri]; }
  // Whether `p` (on triangle `tri`) lies where another face covers it (boxes grown by `margin`,
  // at least by 2 tolerance(): a hit point computed far from the origin is off by float steps).
  bool covers(uint32_t tri, const Eigen::Vector3f& p, float margin = 1e-4f) const;
  float tolerance() const { return tol_; }  // the one used: coincidenceTolerance(mesh, tolerance)
  size_t triangles() const;  // triangles with any coincident part

 private:
  struct Part {
    uint32_t tri;
    Eigen::AlignedBox3f box;  // where another face covers it
  };
  float tol_ = 1e-5f;
  std::vector<uint8_t> has_;   // per triangle
  std::vector<Part> parts_;
  // A uniform grid over the parts: covers() reads one cell (a floor under a hundred pieces of
  // furniture and every wall is hit by most rays of a tilted scanner).
  Eigen::AlignedBox3f bounds_;
  float cell_ = 1.f;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<uint32_t> cell_first_, cell_parts_;  // CSR: parts overlapping each cell, by triangle
  std::vector<uint32_t> cell_tris_;                // the triangle of each cell_parts_ entry
};

}  // namespace polyloc
