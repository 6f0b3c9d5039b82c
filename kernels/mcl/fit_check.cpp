#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/fit_check.hpp>
#include <polyloc/mcl/level_beams.hpp>

#include <cmath>
#include <vector>

namespace polyloc {

ScanFit checkFit(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans, const Pose& map_T_base,
                 double tolerance, size_t beams_per_scan, double past_share) {
  ScanFit fit;
  std::vector<float> ox, oy, oz, dx, dy, dz, tmin, tmax, measured;
  for (const RefineScan& s : scans) {
    if (s.sensor >= rig.size()) continue;
    const Sensor& sensor = rig.sensors[s.sensor];
    const BeamSet all = sensor.beams();
    const Pose S = map_T_base * s.base_T_base_at_scan * sensor.mount;
    for (size_t b : BeamSensorModel::selectBeams(all, s.ranges, beams_per_scan)) {
      const Eigen::Vector3d d = S.rotate(Eigen::Vector3d(all.dx[b], all.dy[b], all.dz[b]));
      if (!isLevelRay(d)) continue;  // level_beams.hpp
      ox.push_back(float(S.x())), oy.push_back(float(S.y())), oz.push_back(float(S.z()));
      dx.push_back(float(d.x())), dy.push_back(float(d.y())), dz.push_back(float(d.z()));
      tmin.push_back(all.range_min), tmax.push_back(all.range_max);
      measured.push_back(s.ranges[b]);
    }
  }
  const size_t n = measured.size();
  if (n == 0) return fit;
  std::vector<float> range(n);
  HitBuffers hits;
  hits.range = range.data();
  caster.castRays(RayBatch{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), tmin.data(), tmax.data(), n}, hits);
  const float tol = float(tolerance);
  std::vector<size_t> longer;
  for (size_t i = 0; i < n; ++i) {
    ++fit.beams;
    if (std::isfinite(range[i]) && measured[i] > range[i] + tol) longer.push_back(i);
    else if (std::isfinite(range[i]) && measured[i] >= range[i] - tol) ++fit.explained;
    else ++fit.shorter;
  }
  if (past_share > 1 || longer.empty()) return fit.longer = longer.size(), fit;
  // The longer beams again, only around their end points: is there a surface there?
  const size_t m = longer.size();
  std::vector<float> lox(m), loy(m), loz(m), ldx(m), ldy(m), ldz(m), lmin(m), lmax(m), lrange(m);
  for (size_t k = 0; k < m; ++k) {
    const size_t i = longer[k];
    lox[k] = ox[i], loy[k] = oy[i], loz[k] = oz[i], ldx[k] = dx[i], ldy[k] = dy[i], ldz[k] = dz[i];
    lmin[k] = measured[i] - tol, lmax[k] = measured[i] + tol;
  }
  HitBuffers behind;
  behind.range = lrange.data();
  caster.castRays(RayBatch{lox.data(), loy.data(), loz.data(), ldx.data(), ldy.data(), ldz.data(), lmin.data(), lmax.data(), m}, behind);
  for (size_t k = 0; k < m; ++k) (std::isfinite(lrange[k]) ? fit.past_surface : fit.longer) += 1;
  // Gone obstacles explain the frame only when (nearly) all its longer beams end on a surface.
  if (double(fit.past_surface) < past_share * double(m)) fit.longer = m, fit.past_surface = 0;
  return fit;
}

}  // namespace polyloc
