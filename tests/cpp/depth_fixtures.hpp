// Helpers of the depth filter tests: synthetic ToF frames of known geometry.
#pragma once

#include <polyloc/depth/filter.hpp>
#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/depth_camera.hpp>

#include <cmath>
#include <functional>
#include <vector>

namespace polyloc::test {

// Depth image (along the optical axis) of whatever `range_of(u, v, base_ray)` returns along
// each pixel's ray; the rays come from DepthCameraSpec::beams(), independently of the filter.
inline std::vector<float> depthImage(const DepthCameraSpec& cam, const Pose& mount,
                                     const std::function<float(int u, int v, const Eigen::Vector3d& ray)>& range_of) {
  const BeamSet b = cam.beams();
  const std::vector<float> factor = cam.depthFactors();
  std::vector<float> depth(cam.numBeams());
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const size_t i = size_t(v) * cam.width + u;
      const Eigen::Vector3d ray = mount.rotate(Eigen::Vector3d(b.dx[i], b.dy[i], b.dz[i]));
      depth[i] = range_of(u, v, ray) * factor[i];
    }
  return depth;
}

// A fronto-parallel wall `distance` m in front of the camera, for every pixel.
inline std::vector<float> flatDepth(const DepthCameraSpec& cam, float distance) {
  return std::vector<float>(cam.numBeams(), distance);
}

inline DepthFrameView view(const DepthCameraSpec& cam, const std::vector<float>& depth,
                           const std::vector<float>* amplitude = nullptr, const std::vector<uint8_t>* rgb = nullptr) {
  return {cam.width, cam.height, depth.data(), amplitude ? amplitude->data() : nullptr, rgb ? rgb->data() : nullptr};
}

}  // namespace polyloc::test
