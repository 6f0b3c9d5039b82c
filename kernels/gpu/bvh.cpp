#include <polyloc/gpu/bvh.hpp>

#include <embree3/rtcore.h>

#include <algorithm>
#include <memory>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

constexpr float kBig = std::numeric_limits<float>::infinity();

// The builder's nodes, in memory Embree's thread-local allocator owns (freed with the RTCBVH).
struct BuildNode {
  bool leaf;
  RTCBounds bounds[2];
  BuildNode* child[2];
  const RTCBuildPrimitive* prims;  // leaf: copied below, the array is Embree's
  unsigned count;
  unsigned first;
};

void* createNode(RTCThreadLocalAllocator alloc, unsigned, void*) {
  auto* n = static_cast<BuildNode*>(rtcThreadLocalAlloc(alloc, sizeof(BuildNode), alignof(BuildNode)));
  *n = BuildNode{false, {}, {nullptr, nullptr}, nullptr, 0, 0};
  return n;
}

void setChildren(void* node, void** children, unsigned count, void*) {
  auto* n = static_cast<BuildNode*>(node);
  for (unsigned i = 0; i < count && i < 2; ++i) n->child[i] = static_cast<BuildNode*>(children[i]);
}

void setBounds(void* node, const RTCBounds** bounds, unsigned count, void*) {
  auto* n = static_cast<BuildNode*>(node);
  for (unsigned i = 0; i < count && i < 2; ++i) n->bounds[i] = *bounds[i];
}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
  auto* n = static_cast<BuildNode*>(rtcThreadLocalAlloc(alloc, sizeof(BuildNode), alignof(BuildNode)));
  // RTCBuildPrimitive is RTC_ALIGN(32): a 16-aligned copy is undefined behaviour (UBSan found it).
  auto* copy = static_cast<RTCBuildPrimitive*>(
      rtcThreadLocalAlloc(alloc, count * sizeof(RTCBuildPrimitive), alignof(RTCBuildPrimitive)));
  std::copy(prims, prims + count, copy);
  *n = BuildNode{true, {}, {nullptr, nullptr}, copy, unsigned(count), 0};
  return n;
}

struct Flattener {
  const Mesh& mesh;
  GpuBvh& out;

  // The reference of child `n` (gpu/bvh.hpp): a leaf's triangles are appended, an inner node's
  // subtree is flattened.
  int32_t ref(const BuildNode* n, int depth) {
    out.depth = std::max(out.depth, depth);
    if (!n->leaf) return inner(n, depth);
    const auto first = uint32_t(out.triangle.size());
    if (first >= (1u << 26)) throw std::invalid_argument("gpu BVH: more than 2^26 triangles");
    for (unsigned i = 0; i < n->count; ++i) {
      const uint32_t t = n->prims[i].primID;
      out.triangle.push_back(t);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f& v = mesh.vertices[mesh.triangles[t][k]];
        out.vertices.insert(out.vertices.end(), {v.x(), v.y(), v.z(), 0.f});
      }
    }
    return gpuBvhLeafRef(first, n->count);
  }

  // Boxes as Embree built them, not padded: a scan at exactly the height of a step's top edge
  // grazes it, and like Embree's the slab test then culls the box (padding made such rays hit).
  static void box(const RTCBounds& b, float* lo, float* hi) {
    lo[0] = b.lower_x, lo[1] = b.lower_y, lo[2] = b.lower_z;
    hi[0] = b.upper_x, hi[1] = b.upper_y, hi[2] = b.upper_z;
  }

  int32_t inner(const BuildNode* n, int depth) {
    const auto at = int32_t(out.nodes.size());
    out.nodes.emplace_back();
    const int32_t l = ref(n->child[0], depth + 1), r = ref(n->child[1], depth + 1);
    GpuBvhNode& g = out.nodes[size_t(at)];
    box(n->bounds[0], g.lmin, g.lmax);
    box(n->bounds[1], g.rmin, g.rmax);
    g.left = l, g.right = r;
    return at;
  }

  // A root that is one leaf: an inner node with that leaf as both children (a walk tests it
  // twice; the same triangles give the same answer).
  void leafRoot(const BuildNode* n, const RTCBounds& all) {
    out.nodes.emplace_back();
    const int32_t l = ref(n, 1);
    GpuBvhNode& g = out.nodes[0];
    box(all, g.lmin, g.lmax);
    box(all, g.rmin, g.rmax);
    g.left = g.right = l;
  }
};

}  // namespace

GpuBvh buildGpuBvh(const Mesh& mesh, int max_leaf_size) {
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(mesh.triangles.size());
  RTCBounds all{kBig, kBig, kBig, 0, -kBig, -kBig, -kBig, 0};
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] >= mesh.vertices.size())
        throw std::invalid_argument("gpu BVH: triangle " + std::to_string(t) + " references a missing vertex");
    if (mesh.triangleNormal(t).isZero()) continue;  // no area: no ray can hit it
    Eigen::Vector3f lo = mesh.vertices[mesh.triangles[t][0]], hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(mesh.vertices[mesh.triangles[t][k]]);
      hi = hi.cwiseMax(mesh.vertices[mesh.triangles[t][k]]);
    }
    prims.push_back(RTCBuildPrimitive{lo.x(), lo.y(), lo.z(), 0, hi.x(), hi.y(), hi.z(), unsigned(t)});
    all.lower_x = std::min(all.lower_x, lo.x()), all.lower_y = std::min(all.lower_y, lo.y());
    all.lower_z = std::min(all.lower_z, lo.z()), all.upper_x = std::max(all.upper_x, hi.x());
    all.upper_y = std::max(all.upper_y, hi.y()), all.upper_z = std::max(all.upper_z, hi.z());
  }
  if (prims.empty()) throw std::invalid_argument("gpu BVH: the map has no triangles with area");
  // Owned: released however this function leaves (a failed allocation while flattening too).
  const std::unique_ptr<RTCDeviceTy, decltype(&rtcReleaseDevice)> owned_device(rtcNewDevice(nullptr), &rtcReleaseDevice);
  RTCDevice device = owned_device.get();
  if (!device) throw std::runtime_error("gpu BVH: cannot create an Embree device");
  const std::unique_ptr<RTCBVHTy, decltype(&rtcReleaseBVH)> owned_bvh(rtcNewBVH(device), &rtcReleaseBVH);
  RTCBVH bvh = owned_bvh.get();
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH; spatial splits would duplicate triangles
  args.maxBranchingFactor = 2;
  args.maxDepth = 48;
  args.minLeafSize = 1;
  args.maxLeafSize = unsigned(std::clamp(max_leaf_size, 1, kGpuBvhMaxLeaf));
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = createNode;
  args.setNodeChildren = setChildren;
  args.setNodeBounds = setBounds;
  args.createLeaf = createLeaf;
  GpuBvh out;
  auto* root = static_cast<BuildNode*>(rtcBuildBVH(&args));
  if (root) {
    out.nodes.reserve(2 * prims.size());
    out.vertices.reserve(12 * prims.size());
    out.triangle.reserve(prims.size());
    Flattener f{mesh, out};
    root->leaf ? f.leafRoot(root, all) : void(f.inner(root, 1));
  }
  const RTCError err = rtcGetDeviceError(device);
  if (!root || err != RTC_ERROR_NONE)
    throw std::runtime_error("gpu BVH: Embree's builder failed (error " + std::to_string(int(err)) + ")");
  return out;
}

}  // namespace polyloc
