// A map whose surfaces are centimetres off, as maps from SLAM or from hand-corrected drawings
// are: every vertex moved in x and y by a smooth random displacement field. The field is value
// noise (independent Gaussian offsets on a square lattice of `correlation` metres, interpolated
// bilinearly and normalised so that every point has std `sigma`), so vertices that coincide move
// alike (closed solids stay closed, touching boxes keep touching) and a wall bends instead of
// breaking into steps. Counter-based random numbers of `seed`: the same map for any thread count.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <cstdint>

namespace polyloc {

struct MeshWarpOptions {
  double sigma = 0.02;        // m, std of each displacement component
  double correlation = 0.5;   // m, lattice spacing of the field (distance over which it changes)
  uint64_t seed = 1;
};

// The displacement at (x, y). Throws std::invalid_argument for sigma < 0 or correlation <= 0.
Eigen::Vector2d warpDisplacement(double x, double y, const MeshWarpOptions& options);

Mesh warpMesh(const Mesh& mesh, const MeshWarpOptions& options);

}  // namespace polyloc
