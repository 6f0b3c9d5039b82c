#include <polyloc/raycast/per_ray_caster.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc {

void PerRayCaster::writeHit(const HitBuffers& out, size_t i, float range, float t1,
                            uint32_t triangle, uint32_t label, const Eigen::Vector3f& n,
                            const CastOptions& opt) {
  const bool hit = std::isfinite(range);
  out.range[i] = hit ? range : (opt.miss_is_max_range ? t1 : std::numeric_limits<float>::infinity());
  if (out.triangle) out.triangle[i] = hit ? triangle : kNoHit;
  if (out.label) out.label[i] = hit ? label : 0;
  if (out.nx) {
    out.nx[i] = hit ? n.x() : 0.f;
    out.ny[i] = hit ? n.y() : 0.f;
    out.nz[i] = hit ? n.z() : 0.f;
  }
}

void PerRayCaster::castScans(std::span<const Pose> poses, const BeamSet& beams,
                             const HitBuffers& out, const ScanWindow& window) const {
  const size_t nb = beams.size();
  if (nb == 0 || poses.empty()) return;
  const CastOptions opt = options;
  parallel(poses.size(), 4, [&](size_t p0, size_t p1) {
    for (size_t p = p0; p < p1; ++p) {
      const Eigen::Matrix3f R = poses[p].rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f o = poses[p].translation().cast<float>();
      for (size_t b = 0; b < nb; ++b) {
        const Eigen::Vector3f d = R * Eigen::Vector3f(beams.dx[b], beams.dy[b], beams.dz[b]);
        const float t0 = window.tmin ? std::max(beams.range_min, window.tmin[b]) : beams.range_min;
        const float t1 = window.tmax ? std::min(beams.range_max, window.tmax[b]) : beams.range_max;
        traceRay(out, p * nb + b, o, d, t0, t1, opt);
      }
    }
  });
}

void PerRayCaster::castRays(const RayBatch& r, const HitBuffers& out) const {
  const CastOptions opt = options;
  parallel(r.count, 128, [&](size_t i0, size_t i1) {
    for (size_t i = i0; i < i1; ++i)
      traceRay(out, i, {r.ox[i], r.oy[i], r.oz[i]}, {r.dx[i], r.dy[i], r.dz[i]},
               r.tmin ? r.tmin[i] : 0.f, r.tmax ? r.tmax[i] : std::numeric_limits<float>::infinity(), opt);
  });
}

}  // namespace polyloc
