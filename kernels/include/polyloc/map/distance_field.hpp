// A 3D distance field of a polygon map: the Euclidean distance (metres) from a point to the
// nearest mesh surface (unsigned), sampled on a regular grid of nodes over the mesh bounds plus
// padding and clamped at max_distance. Used by the likelihood-field measurement model (distance
// of a beam endpoint to the map) and meant to serve sphere tracing and clearance queries too, so
// it knows nothing about MCL.
//
// Build (O(nodes + band), TBB parallel):
//   1. every node within a band of 2 voxels of a triangle gets its exact distance
//      (closestPointOnTriangle against each triangle whose grown bounding box holds it); those
//      nodes are the seeds, each remembering its nearest triangle;
//   2. an exact separable Euclidean distance transform over the node grid (Felzenszwalb and
//      Huttenlocher, one 1D lower envelope of parabolas per line and axis) finds the nearest seed
//      of every other node;
//   3. a node's value is its exact distance to its nearest seed's triangle.
// Storage: uint16 per node in steps of max_distance / 65535 (15 um at 1 m), 2 bytes per node:
// lab.obj at 5 cm with 1 m padding is about 31 M nodes, 62 MB. The build needs 4 more bytes per
// node while it runs.
//
// Error bound (h = resolution), against the true distance D clamped at max_distance:
//   - at a node within 2h of a surface: exact (up to the 15 um quantisation);
//   - at a farther node: the distance to an actual triangle, so never below D; above D only where
//     the nearest seed node belongs to another triangle than the nearest one (near ridges of the
//     distance, e.g. between two walls), by less than h, typically by well under a millimetre;
//   - between nodes, trilinear interpolation of a 1-Lipschitz function adds at most the mean
//     distance to the cell corners (<= 0.87 h); where D is linear (in front of a plane) it adds
//     nothing. The worst case is a point on a surface inside a cell: D = 0 reads up to ~h/2 for an
//     axis-aligned wall halfway between nodes, so use a resolution well below the distances that
//     matter (the likelihood field: resolution <= sigma_hit).
// Outside the grid distance() returns max_distance; with padding >= max_distance that is exact.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace polyloc {

struct DistanceFieldConfig {
  double resolution = 0.05;   // m between grid nodes
  double max_distance = 1.0;  // m; distances clamp here (beyond it a likelihood field is flat)
  double padding = 1.0;       // m added around the mesh bounds; >= max_distance keeps
                              // "outside the grid = max_distance" exact (safe for sphere tracing)
};

class DistanceField3D {
 public:
  // Throws std::invalid_argument for a non-positive resolution or max_distance, a negative
  // padding, or a grid of more than 2^31 nodes. An empty mesh gives an empty grid (every query
  // returns max_distance).
  explicit DistanceField3D(const Mesh& mesh, const DistanceFieldConfig& config = {});

  // Trilinear distance at p (m), in [0, max_distance]; max_distance outside the grid or for NaN.
  float distance(const Eigen::Vector3f& p) const;
  // n points given as plain coordinate arrays; out[i] = distance(point i). Sequential: callers
  // parallelise over their own work (particles, rays).
  void distances(const float* x, const float* y, const float* z, size_t n, float* out) const;

  // The stored value at node (i, j, k) and where the node is.
  float nodeDistance(size_t i, size_t j, size_t k) const { return scale_ * float(q_[index(i, j, k)]); }
  Eigen::Vector3f nodePosition(size_t i, size_t j, size_t k) const {
    return origin_ + resolution_ * Eigen::Vector3f(float(i), float(j), float(k));
  }

  size_t nx() const { return dims_[0]; }
  size_t ny() const { return dims_[1]; }
  size_t nz() const { return dims_[2]; }
  const std::array<size_t, 3>& dims() const { return dims_; }
  size_t numNodes() const { return q_.size(); }
  const Eigen::Vector3f& origin() const { return origin_; }  // node (0, 0, 0)
  float resolution() const { return resolution_; }
  float maxDistance() const { return max_distance_; }
  size_t memoryBytes() const { return q_.capacity() * sizeof(uint16_t); }

 private:
  size_t index(size_t i, size_t j, size_t k) const { return i + dims_[0] * (j + dims_[1] * k); }

  std::array<size_t, 3> dims_{0, 0, 0};
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  float resolution_ = 0.05f, inv_resolution_ = 20.f, max_distance_ = 1.f;
  float scale_ = 1.f;                   // metres per quantisation step
  Eigen::Vector3f upper_{-1, -1, -1};   // largest valid grid coordinate per axis (dims - 1)
  std::vector<uint16_t> q_;             // x fastest, then y, then z
};

// Inline: the hot lookup of the likelihood field (one per beam and particle).
inline float DistanceField3D::distance(const Eigen::Vector3f& p) const {
  const Eigen::Vector3f u = (p - origin_) * inv_resolution_;
  // Written so that NaN fails the test too.
  if (!(u.x() >= 0.f && u.y() >= 0.f && u.z() >= 0.f && u.x() <= upper_.x() && u.y() <= upper_.y() &&
        u.z() <= upper_.z()))
    return max_distance_;
  const size_t i = std::min(size_t(u.x()), dims_[0] - 2), j = std::min(size_t(u.y()), dims_[1] - 2),
               k = std::min(size_t(u.z()), dims_[2] - 2);
  const float fx = u.x() - float(i), fy = u.y() - float(j), fz = u.z() - float(k);
  const size_t sy = dims_[0], sz = dims_[0] * dims_[1];
  const uint16_t* c = q_.data() + index(i, j, k);
  const float c00 = float(c[0]) + fx * (float(c[1]) - float(c[0]));
  const float c10 = float(c[sy]) + fx * (float(c[sy + 1]) - float(c[sy]));
  const float c01 = float(c[sz]) + fx * (float(c[sz + 1]) - float(c[sz]));
  const float c11 = float(c[sz + sy]) + fx * (float(c[sz + sy + 1]) - float(c[sz + sy]));
  const float c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
  return scale_ * (c0 + fz * (c1 - c0));
}

}  // namespace polyloc
