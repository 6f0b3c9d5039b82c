// The beam model's sum over one pose's beams, as a plain function of the hit ranges and per-beam
// terms, and the optional caster capability to evaluate it where the rays are cast: a GPU caster
// casts poses x beams and sums per pose there, so only one number a pose comes back
// (mcl/beam_model.cpp fills the terms; raycast/gpu.cpp and scoreHits evaluate them alike).
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/beams.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

namespace polyloc {

// Per-beam terms of the beam mixture (BeamSensorModel::weighSelected), beams.size() entries each.
struct ScanScoring {
  const float* measured = nullptr;      // z
  const float* miss = nullptr;          // log-density when the window holds no surface
  const float* short_dens = nullptr;    // short-return density at z (d < 0 only)
  const float* hit_scale = nullptr;     // z_hit / (sigma sqrt(2 pi))
  const float* half_inv_var = nullptr;  // 1 / (2 sigma^2)
  float p_rand = 0;                     // z_rand / range_max
  // With one sigma for every beam: the hit density tabulated over |d| (table_size entries) and
  // log(hit + p_rand); lookups replace exp, and for d >= 0 also log. table_size 0: no table.
  const float* hit_table = nullptr;
  const float* log_table = nullptr;
  size_t table_size = 0;
  float inv_step = 0;
};

// Sum of the log-densities of one pose's `beams` hit ranges, in beam order (double accumulator).
inline double scoreHits(const float* h, size_t beams, const ScanScoring& s) {
  double sum = 0;
  for (size_t i = 0; i < beams; ++i) {
    if (!std::isfinite(h[i])) {
      sum += s.miss[i];
      continue;
    }
    const float d = s.measured[i] - h[i];
    if (s.table_size > 0) {
      const float x = std::abs(d) * s.inv_step;
      const size_t k = std::min(size_t(x), s.table_size - 2);
      const float f = std::min(x - float(k), 1.f);
      if (d >= 0) sum += s.log_table[k] + f * (s.log_table[k + 1] - s.log_table[k]);
      else sum += std::log(s.hit_table[k] + f * (s.hit_table[k + 1] - s.hit_table[k]) + s.short_dens[i] + s.p_rand);
      continue;
    }
    const float dens = s.hit_scale[i] * std::exp(-s.half_inv_var[i] * d * d) + (d < 0 ? s.short_dens[i] : 0.f) + s.p_rand;
    sum += std::log(dens);
  }
  return sum;
}

// A caster that scores scans itself. sums[p] = scoreHits over pose p's beams (float precision
// where the caster computes in float), the rays cast as castScans casts them.
class ScanScorer {
 public:
  virtual ~ScanScorer() = default;
  virtual void scoreScans(std::span<const Pose> sensor_poses, const BeamSet& beams, const ScanWindow& window,
                          const ScanScoring& scoring, double* sums) const = 0;
};

}  // namespace polyloc
