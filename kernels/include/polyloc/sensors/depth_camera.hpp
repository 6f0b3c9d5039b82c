// Pinhole depth / ToF camera. Beams are the pixel rays in the sensor body frame (x forward,
// y left, z up), row-major from the top-left pixel. A ToF camera reports depth along the optical
// axis, not range along the ray: depth = range * depthFactor(pixel).
#pragma once

#include <polyloc/sensors/beams.hpp>

namespace polyloc {

struct DepthCameraSpec {
  int width = 64;
  int height = 50;
  double hfov_rad = 0.698131700797732;  // 40 deg
  double vfov_rad = 0.523598775598299;  // 30 deg
  double range_min = 0.1;
  double range_max = 7.5;
  double rate_hz = 20.0;

  // Intrinsics of the equivalent pinhole (pixels; principal point at the image centre).
  double fx() const;
  double fy() const;
  double cx() const { return 0.5 * width; }
  double cy() const { return 0.5 * height; }
  size_t numBeams() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  BeamSet beams() const;
  std::vector<float> depthFactors() const;  // cos(angle between pixel ray and optical axis)
};

DepthCameraSpec pmdO3D100();  // 64x50 px, 40x30 deg, 7.5 m (20 MHz modulation), 20 Hz

}  // namespace polyloc
