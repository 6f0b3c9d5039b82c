// A bounding-volume hierarchy of the map for compute shaders: built by Embree's BVH builder
// (rtcBuildBVH with our node callbacks, binned SAH, two children a node) and flattened into
// plain arrays that upload as storage buffers as they are. Triangles are reordered into leaf
// order; `triangle` maps each back to its index in the Mesh.
#pragma once

#include <polyloc/map/mesh.hpp>

#include <cstdint>
#include <vector>

namespace polyloc {

// 64 bytes, std430-compatible (four vec4): the boxes of both children, so a walk tests them
// where it stands and descends into the nearer first. A child reference `ref` (the int bits of
// lmin.w for the left child, lmax.w for the right): ref >= 0 an inner node's index; ref < 0 a
// leaf: k = -ref - 1, first triangle (leaf order) k >> 4, count k & 15. A root that is one leaf
// has it as both children.
struct GpuBvhNode {
  float lmin[3];
  int32_t left;
  float lmax[3];
  int32_t right;
  float rmin[3];
  int32_t pad0;
  float rmax[3];
  int32_t pad1;
};

inline constexpr int kGpuBvhMaxLeaf = 15;
inline int32_t gpuBvhLeafRef(uint32_t first, uint32_t count) { return -int32_t((first << 4) | count) - 1; }

struct GpuBvh {
  std::vector<GpuBvhNode> nodes;  // nodes[0] is the root, always an inner node
  std::vector<float> vertices;    // 12 floats a triangle in leaf order: v0 xyz _, v1 xyz _, v2 xyz _
  std::vector<uint32_t> triangle; // Mesh triangle index of each leaf-order triangle
  int depth = 0;                  // longest root-to-leaf path (the shader's stack must hold it)
  size_t bytes() const {
    return nodes.size() * sizeof(GpuBvhNode) + vertices.size() * sizeof(float) + triangle.size() * sizeof(uint32_t);
  }
};

// Throws std::invalid_argument for a mesh without triangles (or only degenerate ones) or with a
// triangle naming a missing vertex; std::runtime_error when Embree cannot build. max_leaf_size
// is clamped to [1, kGpuBvhMaxLeaf].
GpuBvh buildGpuBvh(const Mesh& mesh, int max_leaf_size = 4);

}  // namespace polyloc
