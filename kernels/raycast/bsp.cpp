// BspCaster: build (check, union of solids, tree) and the queries. A ray walks the tree front to
// back with an explicit stack (Ericson, Real-Time Collision Detection 8.4.2, extended to report
// the plane it entered through): at a node the part of the window on the origin's side is
// walked first, the far part is pushed. The first leaf whose state differs from the first
// leaf's is the hit.
#include "bsp_tree.hpp"

#include <polyloc/geometry/closest_point.hpp>
#include <polyloc/raycast/bsp.hpp>

#include <chrono>
#include <cmath>
#include <limits>

namespace polyloc {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kStack = 1024;  // > any depth the build allows (BspOptions::max_depth <= this)

struct Crossing {
  float t = kInf;
  int32_t node = -1;      // node whose plane the ray crossed; -1: no crossing in the window
  bool from_solid = false;  // the window starts inside solid (the crossing is a back face)
};

}  // namespace

struct BspCaster::Impl {
  bsp::Tree tree;
  Mesh mesh;  // triangles and labels for hit reporting
  BspStats stats;

  Crossing cross(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t0, float t1) const {
    struct Entry {
      int32_t node;
      float tmax;
      int32_t plane;
    };
    Entry stack[kStack];
    int sp = 0;
    int32_t node = tree.root, entered = -1;
    float tmin = t0, tmax = t1;
    int first = -1;  // state of the first leaf: 0 empty, 1 solid
    for (;;) {
      while (node >= 0) {
        const bsp::Node& n = tree.nodes[node];
        const float dist = n.nx * o.x() + n.ny * o.y() + n.nz * o.z() - n.d;
        const float denom = n.nx * d.x() + n.ny * d.y() + n.nz * d.z();
        // Near side: the origin's; an origin on the plane looks where the ray goes and never
        // crosses it (t = 0 would otherwise send the window to the side it does not enter).
        const int near = dist > 0.f || (dist == 0.f && denom >= 0.f) ? 0 : 1;
        if (denom != 0.f && dist != 0.f) {
          const float t = -dist / denom;
          if (t >= 0.f && t <= tmax) {
            if (t > tmin) {
              stack[sp++] = {n.child[1 - near], tmax, node};
              tmax = t;
            } else {
              node = n.child[1 - near];  // the window lies wholly beyond the plane
              continue;
            }
          }
        }
        node = n.child[near];
      }
      const int state = node == bsp::kSolid ? 1 : 0;
      if (first < 0)
        first = state;
      else if (state != first)
        return {tmin, entered, first == 1};
      if (sp == 0) return {};
      const Entry& e = stack[--sp];
      node = e.node;
      tmin = tmax;
      tmax = e.tmax;
      entered = e.plane;
    }
  }

  // The map triangle on the crossed plane that holds the hit point, else the nearest one.
  uint32_t triangleAt(const bsp::Node& n, const Eigen::Vector3f& p) const {
    uint32_t best = kNoHit;
    float best_d = kInf;
    for (uint32_t k = 0; k < n.tri_count; ++k) {
      const uint32_t t = tree.tris[n.tri_first + k];
      const Triangle& tri = mesh.triangles[t];
      const float dd = (closestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                               mesh.vertices[tri[2]]) - p).squaredNorm();
      if (dd < best_d) {
        best_d = dd;
        best = t;
        if (dd < 1e-10f) break;
      }
    }
    return best;
  }

  void castOne(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t0, float t1,
               const CastOptions& opt, const HitBuffers& out, size_t i) const {
    const Crossing c = t0 <= t1 ? cross(o, d, t0, t1) : Crossing{};
    if (c.node < 0) {
      out.range[i] = opt.miss_is_max_range ? t1 : kInf;
      if (out.triangle) out.triangle[i] = kNoHit;
      if (out.label) out.label[i] = 0;
      if (out.nx) out.nx[i] = out.ny[i] = out.nz[i] = 0.f;
      return;
    }
    out.range[i] = c.from_solid && opt.backface_is_solid ? t0 : c.t;
    const bsp::Node& n = tree.nodes[c.node];
    if (out.triangle || out.label) {
      const uint32_t t = triangleAt(n, o + c.t * d);
      if (out.triangle) out.triangle[i] = t;
      if (out.label) out.label[i] = t == kNoHit ? 0 : mesh.triangle_label[t];
    }
    if (out.nx) {
      // Entering solid the normal faces the ray, leaving it (a back face) it runs along it.
      const float facing = n.nx * d.x() + n.ny * d.y() + n.nz * d.z();
      const float s = (facing > 0.f) == c.from_solid ? 1.f : -1.f;
      out.nx[i] = s * n.nx;
      out.ny[i] = s * n.ny;
      out.nz[i] = s * n.nz;
    }
  }

  bool pointFree(const Eigen::Vector3f& p, float r) const {
    int32_t stack[kStack];
    int sp = 0;
    stack[sp++] = tree.root;
    while (sp > 0) {
      int32_t node = stack[--sp];
      while (node >= 0) {
        const bsp::Node& n = tree.nodes[node];
        const float dist = n.nx * p.x() + n.ny * p.y() + n.nz * p.z() - n.d;
        if (dist >= r) {
          node = n.child[0];
        } else if (dist < -r) {
          node = n.child[1];
        } else {  // the r-ball reaches both sides
          if (sp == kStack) return false;
          stack[sp++] = n.child[1];
          node = n.child[0];
        }
      }
      if (node == bsp::kSolid) return false;
    }
    return true;
  }
};

BspCaster::BspCaster(const Mesh& mesh, const BspOptions& options)
    : PerRayCaster(options.threads), impl_(new Impl) {
  const auto start = std::chrono::steady_clock::now();
  Impl& m = *impl_;
  if (mesh.triangles.empty()) throw std::invalid_argument("BspCaster: the map has no triangles");
  BspOptions opt = options;
  opt.max_depth = std::min(opt.max_depth, kStack - 1);
  bsp::checkClosedOutward(mesh);
  m.mesh = mesh;
  bsp::PlaneSet planes;
  std::vector<bsp::Polygon> polys = bsp::unionBoundary(mesh, planes, opt.plane_eps);
  m.stats.input_triangles = mesh.triangles.size();
  m.stats.boundary_polygons = polys.size();
  int32_t root = bsp::kEmpty;
  const std::vector<bsp::BuildNode> nodes =
      bsp::buildNodes(std::move(polys), planes, opt, m.stats, root);
  m.tree = bsp::compact(nodes, root, planes);
  m.stats.node_bytes = m.tree.nodes.size() * sizeof(bsp::Node);
  m.stats.triangle_ref_bytes = m.tree.tris.size() * sizeof(uint32_t);
  m.stats.build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

BspCaster::~BspCaster() = default;

const BspStats& BspCaster::stats() const { return impl_->stats; }

void BspCaster::traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                         float t0, float t1, const CastOptions& opt) const {
  impl_->castOne(o, d, t0, t1, opt, out, i);
}

void BspCaster::queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                          uint8_t* free) const {
  const Impl& m = *impl_;
  const float r = std::max(clearance, 0.f);
  parallel(points.size(), 256, [&](size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) free[i] = m.pointFree(points[i], r) ? 1 : 0;
  });
}

}  // namespace polyloc
