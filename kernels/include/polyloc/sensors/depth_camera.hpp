// Pinhole depth / ToF camera. Beams are the pixel rays in the sensor body frame (x forward,
// y left, z up), row-major from the top-left pixel. A ToF camera reports depth along the optical
// axis, not range along the ray: depth = range * depthFactor(pixel).
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/beams.hpp>

#include <optional>

namespace polyloc {

struct DepthCameraSpec {
  int width = 64;
  int height = 50;
  double hfov_rad = 0.698131700797732;  // 40 deg
  double vfov_rad = 0.523598775598299;  // 30 deg
  double range_min = 0.1;
  double range_max = 7.5;
  double rate_hz = 20.0;
  // A calibrated pinhole (a real camera's CameraInfo K): when set it replaces the one the fields of
  // view imply. Principal point in polyloc's continuous pixel coordinates, where pixel (u, v)
  // covers [u, u+1) x [v, v+1): cx = K's cx + 0.5 (ROS puts pixel centres on integers).
  struct Pinhole {
    double fx = 0, fy = 0, cx = 0, cy = 0;
  };
  std::optional<Pinhole> pinhole;

  // Intrinsics (pixels): the calibrated pinhole, else the fields of view's with the principal
  // point at the image centre.
  double fx() const;
  double fy() const;
  double cx() const { return pinhole ? pinhole->cx : 0.5 * width; }
  double cy() const { return pinhole ? pinhole->cy : 0.5 * height; }
  size_t numBeams() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  BeamSet beams() const;
  std::vector<float> depthFactors() const;  // cos(angle between pixel ray and optical axis)
};

DepthCameraSpec pmdO3D100();  // 64x50 px, 40x30 deg, 7.5 m (20 MHz modulation), 20 Hz

// optical_T_body: a camera's REP-103 body frame (x forward, y left, z up) in its optical frame
// (x right, y down, z forward), p_optical = opticalFromBody() * p_body. Data sets give
// world_T_optical; world_T_body = world_T_optical * opticalFromBody().
Pose opticalFromBody();

// A camera from a calibration (ROS CameraInfo's K: fx, fy, cx, cy with pixel centres on integers):
// the pinhole set, hfov/vfov the angles its image spans (for whatever reads the fields of view).
// Throws std::invalid_argument naming the value when the size or a focal length is not positive
// and finite, or the principal point lies outside the image.
DepthCameraSpec depthCameraFromIntrinsics(int width, int height, double fx, double fy, double cx_ros, double cy_ros,
                                          double range_min, double range_max, double rate_hz);

}  // namespace polyloc
