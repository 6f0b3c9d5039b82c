#include <polyloc/raycast/octomap.hpp>

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace polyloc {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}

struct OctomapCaster::Impl {
  std::unique_ptr<octomap::OcTree> tree;
  std::unordered_map<octomap::OcTreeKey, uint32_t, octomap::OcTreeKey::KeyHash> voxel_tri;
  std::vector<uint32_t> labels;
  float res = 0.05f;
  Eigen::Vector3f lo, hi;  // metric bounds of the occupied voxels

  bool occ(const octomap::OcTreeKey& k) const {
    const octomap::OcTreeNode* n = tree->search(k);
    return n && tree->isNodeOccupied(n);
  }

  void cast(const HitBuffers& out, size_t idx, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
            float t0, float t1, const CastOptions& opt) const {
    float range = kInf;
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    uint32_t tri = kNoHit;
    // Window clipped to the bounding box, so that misses end there, not at the tree's limits.
    float a = t0, b = t1;
    for (int k = 0; k < 3 && a <= b; ++k) {
      if (std::abs(d[k]) < 1e-12f) {
        if (o[k] < lo[k] || o[k] > hi[k]) a = kInf;
        continue;
      }
      float ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      a = std::max(a, ta), b = std::min(b, tb);
    }
    if (t0 <= t1 && a <= b) {
      const Eigen::Vector3f s = o + t0 * d;  // castRay starts at the window start
      octomap::point3d end;
      const double max_range = std::max(double(b - t0) + res, 1e-6);  // <= 0 would mean unlimited
      if (tree->castRay({s.x(), s.y(), s.z()}, {d.x(), d.y(), d.z()}, end, true, max_range)) {
        const Eigen::Vector3f c(end.x(), end.y(), end.z());
        float tin = -kInf, tout = kInf;
        int face = 0;
        for (int k = 0; k < 3; ++k) {
          if (std::abs(d[k]) < 1e-12f) continue;
          float ta = (c[k] - 0.5f * res - o[k]) / d[k], tb = (c[k] + 0.5f * res - o[k]) / d[k];
          if (ta > tb) std::swap(ta, tb);
          if (ta > tin) tin = ta, face = k;
          tout = std::min(tout, tb);
        }
        float t = tin <= tout ? tin : (c - o).dot(d);
        t = std::max(t, t0);
        if (t <= t1) {
          range = t;
          n[face] = d[face] > 0 ? -1.f : 1.f;
          const auto it = voxel_tri.find(tree->coordToKey(end));
          if (it != voxel_tri.end()) tri = it->second;
        }
      }
    }
    writeHit(out, idx, range, t1, tri, tri != kNoHit ? labels[tri] : 0, n, opt);
  }
};

OctomapCaster::OctomapCaster(const Mesh& mesh, const OctomapOptions& o)
    : PerRayCaster(o.threads), impl_(new Impl) {
  Impl& m = *impl_;
  if (!(o.resolution > 0)) throw std::invalid_argument("OctomapCaster: resolution must be > 0");
  if (mesh.triangles.empty()) throw std::invalid_argument("OctomapCaster: the map has no triangles");
  m.res = float(o.resolution);
  m.labels = mesh.triangle_label;
  m.tree = std::make_unique<octomap::OcTree>(o.resolution);
  const float step = 0.5f * m.res;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3f &a = mesh.vertices[mesh.triangles[t][0]],
                          &b = mesh.vertices[mesh.triangles[t][1]],
                          &c = mesh.vertices[mesh.triangles[t][2]];
    const float e = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, int(std::ceil(e / step)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3f p = a + (b - a) * (float(i) / float(n)) + (c - a) * (float(j) / float(n));
        octomap::OcTreeKey key;
        if (m.tree->coordToKeyChecked(p.x(), p.y(), p.z(), key))
          m.voxel_tri.emplace(key, static_cast<uint32_t>(t));
      }
  }
  const float occupied = m.tree->getClampingThresMaxLog();
  for (const auto& [key, tri] : m.voxel_tri) m.tree->setNodeValue(key, occupied, true);
  m.tree->updateInnerOccupancy();
  double x0, y0, z0, x1, y1, z1;
  m.tree->getMetricMin(x0, y0, z0);
  m.tree->getMetricMax(x1, y1, z1);
  m.lo = Eigen::Vector3f(float(x0), float(y0), float(z0));
  m.hi = Eigen::Vector3f(float(x1), float(y1), float(z1));
}

OctomapCaster::~OctomapCaster() = default;

void OctomapCaster::traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o,
                             const Eigen::Vector3f& d, float t0, float t1,
                             const CastOptions& opt) const {
  impl_->cast(out, i, o, d, t0, t1, opt);
}

size_t OctomapCaster::occupiedVoxels() const { return impl_->voxel_tri.size(); }
bool OctomapCaster::occupied(const Eigen::Vector3f& p) const {
  return impl_->occ(impl_->tree->coordToKey(p.x(), p.y(), p.z()));
}
size_t OctomapCaster::memoryBytes() const {
  // Hash node: key (6 B) + triangle (4 B) + next pointer + cached hash, plus the bucket array.
  const auto& t = impl_->voxel_tri;
  return impl_->tree->memoryUsage() + t.size() * 32 + t.bucket_count() * sizeof(void*);
}

void OctomapCaster::queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                              uint8_t* free) const {
  const Impl& m = *impl_;
  const int r = std::max(0, int(std::ceil(clearance / m.res)));
  parallel(points.size(), 16, [&](size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i) {
      const Eigen::Vector3f& p = points[i];
      octomap::OcTreeKey k;
      if (!p.allFinite() || !m.tree->coordToKeyChecked(p.x(), p.y(), p.z(), k)) {
        free[i] = 0;
        continue;
      }
      bool ok = !m.occ(k);
      for (int dz = -r; ok && dz <= r; ++dz)
        for (int dy = -r; ok && dy <= r; ++dy)
          for (int dx = -r; ok && dx <= r; ++dx) {
            const octomap::OcTreeKey q(uint16_t(k[0] + dx), uint16_t(k[1] + dy), uint16_t(k[2] + dz));
            const octomap::point3d c = m.tree->keyToCoord(q);
            // Distance from p to the voxel cube.
            const Eigen::Vector3f cc(c.x(), c.y(), c.z());
            const Eigen::Vector3f gap = ((p - cc).cwiseAbs().array() - 0.5f * m.res).max(0.f).matrix();
            if (gap.norm() < clearance && m.occ(q)) ok = false;
          }
      free[i] = ok;
    }
  });
}

}  // namespace polyloc
