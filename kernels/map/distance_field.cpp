#include <polyloc/geometry/closest_point.hpp>
#include <polyloc/map/distance_field.hpp>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace polyloc {
namespace {

// Nodes closer than this many voxels to a triangle get exact distances and seed the transform.
// Any point of a surface has a node within 0.87 voxels, so 2 leaves margin for rounding.
constexpr float kBandVoxels = 2.f;
constexpr size_t kSlab = 4;  // z layers per seeding task: tasks own disjoint nodes, no races

// Node labels while building (one int32 per node, so the transform needs no other 3D array):
// >= 0: a seed, the index of its nearest triangle; -1: no seed known yet; <= -2: -(seed node) - 2.
constexpr int32_t kNoSeed = -1;
inline int64_t seedOf(int32_t label, int64_t node) { return label >= 0 ? node : label == kNoSeed ? -1 : -int64_t(label) - 2; }

struct Grid {
  std::array<size_t, 3> n;
  Eigen::Vector3f origin;
  float h;
  double inv_nx = 1.0 / double(n[0]), inv_nxy = 1.0 / double(n[0] * n[1]);
  // Node index -> (i, j, k) by multiplying with reciprocals (an integer division per axis is the
  // bottleneck otherwise); exact after the +-1 correction since nodes < 2^31.
  static int64_t divide(int64_t a, int64_t b, double inv_b) {
    int64_t q = int64_t(double(a) * inv_b);
    if (q * b > a) --q;
    else if ((q + 1) * b <= a) ++q;
    return q;
  }
  std::array<int64_t, 3> coords(int64_t node) const {
    const int64_t nx = int64_t(n[0]), nxy = int64_t(n[0] * n[1]);
    const int64_t k = divide(node, nxy, inv_nxy), rest = node - k * nxy, j = divide(rest, nx, inv_nx);
    return {rest - j * nx, j, k};
  }
  Eigen::Vector3f position(int64_t i, int64_t j, int64_t k) const {
    return origin + h * Eigen::Vector3f(float(i), float(j), float(k));
  }
};

// Step 1: exact distances within the band; labels[node] = nearest triangle there, else kNoSeed.
void seedBand(const Mesh& mesh, const Grid& g, int32_t* labels) {
  const float band = kBandVoxels * g.h, band2 = band * band;
  const size_t nx = g.n[0], ny = g.n[1], nz = g.n[2];
  const size_t slabs = (nz + kSlab - 1) / kSlab;
  struct Box { int64_t lo[3], hi[3]; };
  std::vector<Box> boxes(mesh.numTriangles());
  std::vector<std::vector<uint32_t>> bins(slabs);
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    Eigen::AlignedBox3f b;
    for (uint32_t v : tri) b.extend(mesh.vertices[v]);
    Box& box = boxes[t];
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::max<int64_t>(0, int64_t(std::ceil((b.min()[a] - band - g.origin[a]) / g.h)));
      box.hi[a] = std::min<int64_t>(int64_t(g.n[a]) - 1, int64_t(std::floor((b.max()[a] + band - g.origin[a]) / g.h)));
    }
    if (box.lo[0] > box.hi[0] || box.lo[1] > box.hi[1] || box.lo[2] > box.hi[2]) continue;
    for (size_t s = size_t(box.lo[2]) / kSlab; s <= size_t(box.hi[2]) / kSlab; ++s) bins[s].push_back(uint32_t(t));
  }
  // Squared distance so far per node of a slab, one buffer per thread (fresh pages per slab would
  // cost more than the seeding itself).
  tbb::enumerable_thread_specific<std::vector<float>> buffers;
  tbb::parallel_for(size_t(0), slabs, [&](size_t s) {
    const int64_t k0 = int64_t(s * kSlab), k1 = std::min<int64_t>(int64_t(nz), k0 + int64_t(kSlab));
    std::vector<float>& best = buffers.local();
    best.assign(nx * ny * size_t(k1 - k0), band2);
    int32_t* lab = labels + size_t(k0) * nx * ny;
    std::fill(lab, lab + best.size(), kNoSeed);
    for (uint32_t t : bins[s]) {
      const Triangle& tri = mesh.triangles[t];
      const Eigen::Vector3f &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
      const Eigen::Vector3f nrm = mesh.triangleNormal(t);
      const bool planar = nrm.squaredNorm() > 0.5f;  // degenerate triangles: no plane shortcut
      const Box& box = boxes[t];
      for (int64_t k = std::max(box.lo[2], k0); k <= std::min(box.hi[2], k1 - 1); ++k)
        for (int64_t j = box.lo[1]; j <= box.hi[1]; ++j)
          for (int64_t i = box.lo[0]; i <= box.hi[0]; ++i) {
            const Eigen::Vector3f p = g.position(i, j, k);
            if (planar && std::abs(nrm.dot(p - a)) >= band) continue;  // cheap: most of a big box
            const float d2 = (p - closestPointOnTriangle(p, a, b, c)).squaredNorm();
            const size_t local = size_t(i) + nx * (size_t(j) + ny * size_t(k - k0));
            if (d2 < best[local]) best[local] = d2, lab[local] = int32_t(t);
          }
    }
  });
}

// Step 2, one axis: every node's nearest seed among the nearest seeds of the nodes on its line
// (Felzenszwalb & Huttenlocher's lower envelope of parabolas, exact on the integer grid).
void transformAxis(const Grid& g, int axis, int32_t* labels) {
  const int64_t nx = int64_t(g.n[0]), ny = int64_t(g.n[1]), nz = int64_t(g.n[2]);
  const int64_t n = int64_t(g.n[axis]);
  const int64_t stride = axis == 0 ? 1 : axis == 1 ? nx : nx * ny;
  const int64_t other = (nx * ny * nz) / n;  // lines along the axis
  tbb::parallel_for(tbb::blocked_range<int64_t>(0, other, 64), [&](const tbb::blocked_range<int64_t>& r) {
    const size_t len = size_t(n);
    std::vector<double> f(len), zb(len + 1);
    std::vector<int64_t> seed(len), v(len);
    for (int64_t line = r.begin(); line < r.end(); ++line) {
      // First node of the line: the line index enumerates the two other axes, x fastest.
      const int64_t base = axis == 0 ? line * nx : axis == 1 ? (line % nx) + (line / nx) * nx * ny : line;
      int64_t found = 0;
      auto a = g.coords(base);
      for (int64_t p = 0; p < n; ++p, ++a[axis]) {
        const int64_t node = base + p * stride;
        seed[p] = seedOf(labels[size_t(node)], node);
        if (seed[p] < 0) {
          f[p] = std::numeric_limits<double>::infinity();
          continue;
        }
        if (seed[p] == node) {
          f[p] = 0;
          ++found;
          continue;
        }
        const auto b = g.coords(seed[p]);
        f[p] = double((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
        ++found;
      }
      if (found == 0) continue;  // nothing to spread along this line
      // Lower envelope of the parabolas (p - q)^2 + f(q) of the nodes q that have a seed.
      int64_t m = -1;
      for (int64_t q = 0; q < n; ++q) {
        if (!std::isfinite(f[q])) continue;
        double s = -std::numeric_limits<double>::infinity();
        while (m >= 0) {
          const int64_t u = v[m];
          s = ((f[q] + double(q * q)) - (f[u] + double(u * u))) / double(2 * (q - u));
          if (s > zb[m]) break;
          --m;
        }
        ++m;
        v[m] = q;
        zb[m] = m == 0 ? -std::numeric_limits<double>::infinity() : s;
        zb[m + 1] = std::numeric_limits<double>::infinity();
      }
      for (int64_t p = 0, e = 0; p < n; ++p) {
        while (zb[e + 1] < double(p)) ++e;
        const int64_t node = base + p * stride;
        int32_t& lab = labels[size_t(node)];
        if (lab >= 0) continue;  // a seed is its own nearest seed
        lab = int32_t(-seed[v[e]] - 2);
      }
    }
  });
}

}  // namespace

DistanceField3D::DistanceField3D(const Mesh& mesh, const DistanceFieldConfig& cfg) {
  if (!(cfg.resolution > 0)) throw std::invalid_argument("distance field: resolution must be > 0");
  if (!(cfg.max_distance > 0)) throw std::invalid_argument("distance field: max_distance must be > 0");
  if (!(cfg.padding >= 0)) throw std::invalid_argument("distance field: padding must be >= 0");
  resolution_ = float(cfg.resolution), inv_resolution_ = float(1.0 / cfg.resolution);
  max_distance_ = float(cfg.max_distance);
  scale_ = max_distance_ / 65535.f;
  if (mesh.numTriangles() == 0) return;
  const Eigen::AlignedBox3f b = mesh.bounds();
  origin_ = b.min() - Eigen::Vector3f::Constant(float(cfg.padding));
  size_t total = 1;
  for (int a = 0; a < 3; ++a) {
    const double extent = double(b.max()[a] - b.min()[a]) + 2 * cfg.padding;
    dims_[a] = size_t(std::ceil(extent / cfg.resolution - 1e-6)) + 1;
    dims_[a] = std::max<size_t>(dims_[a], 2);
    upper_[a] = float(dims_[a] - 1);
    total *= dims_[a];
    if (total > size_t(std::numeric_limits<int32_t>::max() - 2))
      throw std::invalid_argument("distance field: grid of more than 2^31 nodes (" + std::to_string(dims_[0]) +
                                  " x " + std::to_string(dims_[1]) + " x " + std::to_string(dims_[2]) +
                                  "...): use a coarser resolution or less padding");
  }
  const Grid g{dims_, origin_, resolution_};
  // Not value-initialised: seedBand writes every label (saves clearing 4 bytes a node).
  const std::unique_ptr<int32_t[]> labels(new int32_t[total]);
  seedBand(mesh, g, labels.get());
  for (int axis = 0; axis < 3; ++axis) transformAxis(g, axis, labels.get());

  // Step 3: exact distance to the nearest seed's triangle. A node whose nearest seed is farther
  // than max_distance + band cannot be closer than max_distance to any surface: no test needed.
  q_.assign(total, 65535);
  const float reach = max_distance_ + kBandVoxels * resolution_;
  const float inv_scale = 1.f / scale_;
  tbb::parallel_for(size_t(0), dims_[2], [&](size_t k) {
    for (size_t j = 0; j < dims_[1]; ++j) {
      for (size_t i = 0; i < dims_[0]; ++i) {
        const int64_t node = int64_t(index(i, j, k));
        const int64_t s = seedOf(labels[size_t(node)], node);
        if (s < 0) continue;
        const Eigen::Vector3f p = g.position(int64_t(i), int64_t(j), int64_t(k));
        const auto sc = g.coords(s);
        if ((p - g.position(sc[0], sc[1], sc[2])).squaredNorm() > reach * reach) continue;
        const Triangle& tri = mesh.triangles[size_t(labels[size_t(s)])];
        const float d = (p - closestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                                    mesh.vertices[tri[2]])).norm();
        q_[size_t(node)] = uint16_t(std::min(d, max_distance_) * inv_scale + 0.5f);
      }
    }
  });
}

void DistanceField3D::distances(const float* x, const float* y, const float* z, size_t n, float* out) const {
  for (size_t i = 0; i < n; ++i) out[i] = distance(Eigen::Vector3f(x[i], y[i], z[i]));
}

}  // namespace polyloc
