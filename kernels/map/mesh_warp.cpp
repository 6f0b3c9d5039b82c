#include <polyloc/map/mesh_warp.hpp>
#include <polyloc/geometry/random.hpp>

#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {

constexpr uint64_t kWarpStream = 0x575250ULL << 40;

uint64_t latticeIndex(int64_t i, int64_t j) {
  return (uint64_t(uint32_t(int32_t(i))) << 32) | uint64_t(uint32_t(int32_t(j)));
}

}  // namespace

Eigen::Vector2d warpDisplacement(double x, double y, const MeshWarpOptions& o) {
  if (!(o.sigma >= 0) || !std::isfinite(o.sigma)) throw std::invalid_argument("mesh warp: sigma must be >= 0");
  if (!(o.correlation > 0) || !std::isfinite(o.correlation)) throw std::invalid_argument("mesh warp: correlation must be > 0");
  const CounterRng rng(o.seed);
  const double u = x / o.correlation, v = y / o.correlation;
  const int64_t i0 = int64_t(std::floor(u)), j0 = int64_t(std::floor(v));
  const double fu = u - double(i0), fv = v - double(j0);
  Eigen::Vector2d d = Eigen::Vector2d::Zero();
  double w2 = 0;
  for (int di = 0; di < 2; ++di)
    for (int dj = 0; dj < 2; ++dj) {
      const double w = (di ? fu : 1 - fu) * (dj ? fv : 1 - fv);
      const uint64_t idx = latticeIndex(i0 + di, j0 + dj);
      d += w * Eigen::Vector2d(rng.normal(kWarpStream, idx, 0), rng.normal(kWarpStream, idx, 1));
      w2 += w * w;
    }
  // A bilinear mix of independent values has variance sum(w^2) times theirs: normalised back.
  return o.sigma * d / std::sqrt(w2);
}

Mesh warpMesh(const Mesh& mesh, const MeshWarpOptions& o) {
  Mesh out = mesh;
  for (Eigen::Vector3f& p : out.vertices) {
    const Eigen::Vector2d d = warpDisplacement(p.x(), p.y(), o);
    p.x() += float(d.x()), p.y() += float(d.y());
  }
  return out;
}

}  // namespace polyloc
