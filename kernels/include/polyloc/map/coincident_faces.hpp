// Triangles that lie on a triangle facing the other way. Where two closed solids touch (a cabinet
// against a wall, furniture standing on the floor slab, the boxes of an extruded grid) their faces
// coincide: a ray from inside one meets its exit face and the neighbour's entry face at one
// distance, and which of the two a ray caster reports may depend on its traversal order
// (raycast/embree.cpp settles such ties).
#pragma once

#include <polyloc/map/mesh.hpp>

#include <cstdint>
#include <vector>

namespace polyloc {

// Per triangle, 1 when another triangle lies in its plane (normals opposite within about 1e-3,
// offsets within `tolerance` metres) and their extents overlap with positive area. Degenerate
// triangles are 0.
std::vector<uint8_t> coincidentFaces(const Mesh& mesh, float tolerance = 1e-5f);

}  // namespace polyloc
