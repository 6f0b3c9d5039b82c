// Map validation: what a robotics engineer needs to know before trusting a mesh for ray casting
// and point-in-solid tests.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Geometry>
#include <string>

namespace polyloc {

struct ValidationReport {
  size_t triangles = 0;
  size_t vertices = 0;
  size_t open_edges = 0;          // edges used by exactly one triangle (holes, borders)
  size_t non_manifold_edges = 0;  // edges used by three or more triangles
  size_t inconsistent_edges = 0;  // shared edges traversed in the same direction by both (flipped winding)
  size_t degenerate_triangles = 0;  // zero area (below area_eps) or repeated vertex index
  Eigen::AlignedBox3f bounds;
  std::vector<std::pair<std::string, size_t>> label_counts;  // label -> triangle count

  bool closed() const { return open_edges == 0 && non_manifold_edges == 0; }
  bool consistentWinding() const { return inconsistent_edges == 0; }
  std::string summary() const;  // multi-line human-readable report
};

ValidationReport validateMesh(const Mesh& mesh, float area_eps = 1e-10f);

}  // namespace polyloc
