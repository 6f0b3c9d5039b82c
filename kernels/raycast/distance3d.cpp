#include <polyloc/raycast/distance3d.hpp>


#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}

struct Distance3dCaster::Impl {
  std::unique_ptr<DistanceField3D> field;
  float h = 0.05f, eps = 0.025f;
  int max_steps = 1000;
  Eigen::Vector3f lo, hi;  // grid box (node positions)
  size_t nx = 0, ny = 0, nz = 0, words = 0;  // words per inside-mark row
  std::vector<uint64_t> inside;              // bit per node, rows padded to whole words

  bool insideNode(const Eigen::Vector3f& p) const {
    if (inside.empty()) return false;
    const Eigen::Vector3f u = (p - lo) / h;
    if (!(u.minCoeff() >= -0.5f && u.x() < float(nx) - 0.5f && u.y() < float(ny) - 0.5f &&
          u.z() < float(nz) - 0.5f))
      return false;
    const size_t i = size_t(u.x() + 0.5f), j = size_t(u.y() + 0.5f), k = size_t(u.z() + 0.5f);
    return (inside[(k * ny + j) * words + i / 64] >> (i % 64)) & 1u;
  }

  // Winding number of the mesh along each node row (a line parallel to x), crossings counted
  // +1 where the line enters a solid (normal.x < 0), -1 where it leaves.
  void markInside(const Mesh& mesh) {
    words = (nx + 63) / 64;
    inside.assign(ny * nz * words, 0);
    const float oy = 0.01234f * h, oz = 0.02345f * h;  // off the lattice: rows miss mesh edges
    std::vector<std::vector<std::pair<float, int>>> rows(ny * nz);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Eigen::Vector3f &a = mesh.vertices[mesh.triangles[t][0]],
                            &b = mesh.vertices[mesh.triangles[t][1]],
                            &c = mesh.vertices[mesh.triangles[t][2]];
      const Eigen::Vector3f n = (b - a).cross(c - a);
      if (n.x() == 0.f) continue;  // parallel to the rows
      const Eigen::Vector3f mn = a.cwiseMin(b).cwiseMin(c), mx = a.cwiseMax(b).cwiseMax(c);
      const long j0 = std::max(0L, long(std::ceil((mn.y() - lo.y() - oy) / h)));
      const long j1 = std::min(long(ny) - 1, long(std::floor((mx.y() - lo.y() - oy) / h)));
      const long k0 = std::max(0L, long(std::ceil((mn.z() - lo.z() - oz) / h)));
      const long k1 = std::min(long(nz) - 1, long(std::floor((mx.z() - lo.z() - oz) / h)));
      for (long k = k0; k <= k1; ++k)
        for (long j = j0; j <= j1; ++j) {
          const float y = lo.y() + float(j) * h + oy, z = lo.z() + float(k) * h + oz;
          // Point (y, z) in the triangle's yz projection: edge functions of one sign.
          const auto edge = [&](const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
            return (q.y() - p.y()) * (z - p.z()) - (q.z() - p.z()) * (y - p.y());
          };
          const float e0 = edge(a, b), e1 = edge(b, c), e2 = edge(c, a);
          if (!((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0))) continue;
          // x on the triangle's plane at (y, z).
          const float x = a.x() - (n.y() * (y - a.y()) + n.z() * (z - a.z())) / n.x();
          rows[size_t(k) * ny + size_t(j)].emplace_back(x, n.x() < 0 ? 1 : -1);
        }
    }
    for (size_t r = 0; r < rows.size(); ++r) {
      auto& xs = rows[r];
      std::sort(xs.begin(), xs.end());
      int w = 0;
      for (size_t q = 0; q + 1 < xs.size(); ++q) {
        w += xs[q].second;
        if (w <= 0) continue;
        const long i0 = std::max(0L, long(std::ceil((xs[q].first - lo.x()) / h)));
        const long i1 = std::min(long(nx) - 1, long(std::floor((xs[q + 1].first - lo.x()) / h)));
        for (long i = i0; i <= i1; ++i) inside[r * words + size_t(i) / 64] |= uint64_t(1) << (i % 64);
      }
    }
  }

  // Entry/exit of o + t d with the grid box.
  bool clip(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float& a, float& b) const {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(d[k]) < 1e-12f) {
        if (o[k] < lo[k] || o[k] > hi[k]) return false;
        continue;
      }
      float ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      a = std::max(a, ta);
      b = std::min(b, tb);
    }
    return a <= b;
  }

  void cast(const HitBuffers& out, size_t idx, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
            float t0, float t1, const CastOptions& opt) const {
    float hit = kInf;
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    float a = t0, b = t1;
    if (t0 <= t1 && clip(o, d, a, b)) {
      float t = a;
      int steps = 0;
      if (insideNode(o + t * d)) {
        if (opt.backface_is_solid && t == t0) hit = t0, n = -d;
        else
          while (steps++ < max_steps && t <= b && insideNode(o + t * d)) t += 0.5f * h;
      }
      for (; !std::isfinite(hit) && steps < max_steps && t <= b; ++steps) {
        const float dist = field->distance(o + t * d);
        if (dist < eps) {
          // Newton step onto the zero crossing, slope from a sample just behind.
          const float delta = 0.25f * h;
          const float g = (dist - field->distance(o + (t - delta) * d)) / delta;
          const float th = g < -0.1f ? std::min(t + dist / -g, t + 2.f * eps) : t;
          if (th <= t1) hit = std::max(th, t0);
          n = gradient(o + (std::max(t0, th - eps)) * d);
          if (n.squaredNorm() == 0.f) n = -d;
          break;
        }
        t += dist;
      }
    }
    writeHit(out, idx, hit, t1, kNoHit, 0, n, opt);
  }

  Eigen::Vector3f gradient(const Eigen::Vector3f& p) const {
    Eigen::Vector3f g;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3f e = Eigen::Vector3f::Zero();
      e[k] = 0.5f * h;
      g[k] = field->distance(p + e) - field->distance(p - e);
    }
    const float len = g.norm();
    return len > 0 ? Eigen::Vector3f(g / len) : Eigen::Vector3f::Zero();
  }

};

Distance3dCaster::Distance3dCaster(const Mesh& mesh, const Distance3dOptions& o)
    : PerRayCaster(o.threads), impl_(new Impl) {
  Impl& m = *impl_;
  if (mesh.triangles.empty()) throw std::invalid_argument("Distance3dCaster: the map has no triangles");
  m.field = std::make_unique<DistanceField3D>(mesh, o.field);
  m.h = m.field->resolution();
  m.eps = o.hit_epsilon > 0 ? float(o.hit_epsilon) : 0.5f * m.h;
  m.max_steps = o.max_steps;
  m.nx = m.field->nx(), m.ny = m.field->ny(), m.nz = m.field->nz();
  m.lo = m.field->origin();
  m.hi = m.lo + m.h * Eigen::Vector3f(float(m.nx - 1), float(m.ny - 1), float(m.nz - 1));
  if (o.mark_inside && m.nx > 1) m.markInside(mesh);
}

Distance3dCaster::~Distance3dCaster() = default;

void Distance3dCaster::traceRay(const HitBuffers& out, size_t i, const Eigen::Vector3f& o,
                                const Eigen::Vector3f& d, float t0, float t1,
                                const CastOptions& opt) const {
  impl_->cast(out, i, o, d, t0, t1, opt);
}

const DistanceField3D& Distance3dCaster::field() const { return *impl_->field; }
bool Distance3dCaster::inside(const Eigen::Vector3f& p) const { return impl_->insideNode(p); }
size_t Distance3dCaster::memoryBytes() const {
  return impl_->field->memoryBytes() + impl_->inside.capacity() * sizeof(uint64_t);
}

void Distance3dCaster::queryFree(std::span<const Eigen::Vector3f> points, float clearance,
                                 uint8_t* free) const {
  const Impl& m = *impl_;
  parallel(points.size(), 256, [&](size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i)
      free[i] = !m.insideNode(points[i]) && m.field->distance(points[i]) >= clearance;
  });
}

}  // namespace polyloc
