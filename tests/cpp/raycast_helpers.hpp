// Helpers for the ray-caster backend tests: one ray through any RayCaster, and the agreement of a
// backend with Embree on planar scans of a map.
#pragma once

#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/workload.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace polyloc::test {

inline constexpr float kInfRange = std::numeric_limits<float>::infinity();

inline float castOne(const RayCaster& c, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                     float t0 = 0.f, float t1 = kInfRange) {
  const Eigen::Vector3f u = d.normalized();
  const RayBatch r{&o.x(), &o.y(), &o.z(), &u.x(), &u.y(), &u.z(), &t0, &t1, 1};
  float range = 0;
  c.castRays(r, {&range});
  return range;
}

inline bool freeAt(const RayCaster& c, const Eigen::Vector3f& p, float clearance) {
  uint8_t f = 2;
  c.queryFree(std::span<const Eigen::Vector3f>(&p, 1), clearance, &f);
  return f == 1;
}

struct Agreement {
  double median = 0, p75 = 0;   // |range - embree| over rays both hit, m
  double hit_disagreement = 0;  // fraction of rays where one hits and the other misses
  size_t both_hit = 0;
};

// Planar scans at `height` from random poses inside the map's box, 10 m range limit. The tail of
// the error is not the resolution: rays passing within a cell of a chair leg or table edge hit it
// in a grid (and not in the mesh), and poses inside thin solids read 0 in one and not the other,
// so the tests bound the median and the 75th percentile.
inline Agreement agreeWithEmbree(const RayCaster& c, const Mesh& mesh, size_t poses, size_t beams,
                                 double height) {
  const EmbreeCaster ref(mesh);
  const std::vector<Pose> p = randomPlanarPoses(mesh.bounds(), poses, height, 7);
  const BeamSet b = horizontalFan(beams, 10.f);
  std::vector<float> r(p.size() * b.size()), e(r.size());
  c.castScans(p, b, {r.data()});
  ref.castScans(p, b, {e.data()});
  std::vector<double> err;
  size_t dis = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    const bool a = std::isfinite(r[i]), h = std::isfinite(e[i]);
    dis += a != h;
    if (a && h) err.push_back(std::abs(double(r[i]) - double(e[i])));
  }
  std::sort(err.begin(), err.end());
  Agreement g;
  g.both_hit = err.size();
  g.hit_disagreement = double(dis) / double(r.size());
  if (!err.empty()) g.median = err[err.size() / 2], g.p75 = err[err.size() * 3 / 4];
  return g;
}

}  // namespace polyloc::test
