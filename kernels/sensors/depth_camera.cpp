#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/depth_camera.hpp>

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

namespace polyloc {

double DepthCameraSpec::fx() const { return pinhole ? pinhole->fx : 0.5 * width / std::tan(0.5 * hfov_rad); }
double DepthCameraSpec::fy() const { return pinhole ? pinhole->fy : 0.5 * height / std::tan(0.5 * vfov_rad); }

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

Pose opticalFromBody() {
  // Columns: the body's x (forward), y (left), z (up) in optical coordinates.
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  return Pose::fromMatrix(m);
}

DepthCameraSpec depthCameraFromIntrinsics(int width, int height, double fx, double fy, double cx_ros, double cy_ros,
                                          double range_min, double range_max, double rate_hz) {
  auto bad = [](const char* what, double v, const char* why) {
    return std::invalid_argument(fmt::format("camera intrinsics: {} = {:g} {}", what, v, why));
  };
  if (width < 1 || width > 4096) throw bad("width", width, "must be in [1, 4096] pixels");
  if (height < 1 || height > 4096) throw bad("height", height, "must be in [1, 4096] pixels");
  for (auto [what, v] : {std::pair{"fx", fx}, std::pair{"fy", fy}})
    if (!std::isfinite(v) || v <= 0 || v > 1e6) throw bad(what, v, "must be a positive focal length in pixels");
  if (!std::isfinite(cx_ros) || cx_ros < -0.5 || cx_ros > width - 0.5) throw bad("cx", cx_ros, "lies outside the image");
  if (!std::isfinite(cy_ros) || cy_ros < -0.5 || cy_ros > height - 0.5) throw bad("cy", cy_ros, "lies outside the image");
  if (!(range_min >= 0 && range_max > range_min && std::isfinite(range_max)))
    throw bad("range_max", range_max, "must be finite and above range_min");
  DepthCameraSpec c;
  c.width = width;
  c.height = height;
  c.pinhole = DepthCameraSpec::Pinhole{fx, fy, cx_ros + 0.5, cy_ros + 0.5};
  // The angles from the left to the right and the top to the bottom image edge.
  c.hfov_rad = std::atan((cx_ros + 0.5) / fx) + std::atan((width - cx_ros - 0.5) / fx);
  c.vfov_rad = std::atan((cy_ros + 0.5) / fy) + std::atan((height - cy_ros - 0.5) / fy);
  c.range_min = range_min;
  c.range_max = range_max;
  c.rate_hz = rate_hz > 0 && std::isfinite(rate_hz) ? rate_hz : 30.0;
  return c;
}

}  // namespace polyloc
