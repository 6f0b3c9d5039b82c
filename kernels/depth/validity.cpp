// Validity: what is wrong with a pixel on its own (see stages.hpp).
#include "stages.hpp"

#include <cmath>

namespace polyloc::depth_detail {

void checkValidity(const DepthFrameView& frame, const DepthValidity& c, float range_min, float range_max,
                   const float* range_per_depth, Work& work) {
  const size_t n = work.size();
  const float amin = static_cast<float>(c.amplitude_min);
  for (size_t i = 0; i < n; ++i) {
    const float d = frame.depth[i];
    work.depth[i] = d;
    work.reason[i] = DepthReject::kKept;
    // !(d > 0) also catches NaN; inf is no measurement either (REP-117 "no return").
    if (!(d > 0.f) || !std::isfinite(d)) {
      work.reject(i, DepthReject::kNoMeasurement);
      continue;
    }
    const float r = d * range_per_depth[i];
    if (r < range_min || r > range_max) {
      work.reject(i, DepthReject::kRange);
      continue;
    }
    if (frame.amplitude) {
      const float a = frame.amplitude[i];
      if (!(a >= amin) || !std::isfinite(a)) work.reject(i, DepthReject::kAmplitude);
    }
  }
}

}  // namespace polyloc::depth_detail
