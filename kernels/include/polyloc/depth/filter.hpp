// ToF/PMD depth filtering: validity (range, amplitude), jump-edge (flying pixel) removal,
// the confidence filter of the thesis (eq. 6.4), median or bilateral smoothing, and the kept
// pixels as points in the robot's base frame. A kernel: no threads of its own in apply(); the
// batch call spreads frames over the TBB arena it runs in.
//
//   DepthFilter f(pmdO3D100(), base_T_camera, config);
//   DepthFilterResult r;
//   f.apply({64, 50, depth.data(), amplitude.data()}, r);   // r.valid, r.depth, r.x/y/z
//
// Results are reused: a result passed again of the same size is refilled without allocating.
#pragma once

#include <polyloc/depth/config.hpp>
#include <polyloc/depth/frame.hpp>
#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/depth_camera.hpp>

#include <span>
#include <vector>

namespace polyloc {

class DepthFilter {
 public:
  // Throws std::invalid_argument for settings that cannot work (an odd median size, neighbours
  // not 4 or 8, an empty camera), naming the setting.
  DepthFilter(const DepthCameraSpec& camera, const Pose& base_T_sensor, DepthFilterConfig config = {});

  const DepthCameraSpec& camera() const { return camera_; }
  const DepthFilterConfig& config() const { return config_; }

  // Throws std::invalid_argument when the frame's size is not the camera's or depth is null;
  // bad values (NaN, inf, negative) are rejected pixels, never errors.
  void apply(const DepthFrameView& frame, DepthFilterResult& out) const;
  // Every frame into its result, frames in parallel (TBB). Sizes must match.
  void applyBatch(std::span<const DepthFrameView> frames, std::span<DepthFilterResult> out) const;

 private:
  DepthCameraSpec camera_;
  Pose base_T_sensor_;
  DepthFilterConfig config_;
  float range_min_, range_max_;
  // Per pixel: normalised image coordinates (optical frame: x right, y down, z = 1), the range
  // per unit depth, and the base-frame direction per unit depth (point = t + depth * q).
  std::vector<float> xn_, yn_, range_per_depth_, qx_, qy_, qz_;
};

}  // namespace polyloc
