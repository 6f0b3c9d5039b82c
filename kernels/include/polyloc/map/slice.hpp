// Horizontal slice of a mesh: the line segments where triangles cross the plane z = height.
// What a horizontal 2D scanner at that height sees; the base of top-view plots and 2D grids.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <vector>

namespace polyloc {

struct SliceSegment {
  Eigen::Vector2f a, b;
  uint32_t triangle;
  uint32_t label;
};

std::vector<SliceSegment> sliceMesh(const Mesh& mesh, float height);

}  // namespace polyloc
