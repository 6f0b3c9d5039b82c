#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/depth_camera.hpp>

#include <cmath>

namespace polyloc {

double DepthCameraSpec::fx() const { return 0.5 * width / std::tan(0.5 * hfov_rad); }
double DepthCameraSpec::fy() const { return 0.5 * height / std::tan(0.5 * vfov_rad); }

// Pixel (u, v) centre in the optical frame is ((u+0.5-cx)/fx, (v+0.5-cy)/fy, 1) with x right,
// y down, z forward; in the body frame that is (z, -x, -y).
BeamSet DepthCameraSpec::beams() const {
  BeamSet b;
  b.range_min = static_cast<float>(range_min);
  b.range_max = static_cast<float>(range_max);
  const double ifx = 1.0 / fx(), ify = 1.0 / fy();
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const double ox = (u + 0.5 - cx()) * ifx, oy = (v + 0.5 - cy()) * ify;
      const double inv = 1.0 / std::sqrt(ox * ox + oy * oy + 1.0);
      b.push(static_cast<float>(inv), static_cast<float>(-ox * inv), static_cast<float>(-oy * inv));
    }
  }
  return b;
}

std::vector<float> DepthCameraSpec::depthFactors() const {
  const BeamSet b = beams();
  return b.dx;  // the forward component of each unit ray is its cosine to the optical axis
}

DepthCameraSpec pmdO3D100() { return {}; }

}  // namespace polyloc
