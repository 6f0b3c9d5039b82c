#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/planar_scanner.hpp>

#include <cmath>

namespace polyloc {

// The small epsilon keeps 240 deg / 0.36 deg style specs from losing the last beam to rounding.
size_t PlanarScannerSpec::numBeams() const {
  return static_cast<size_t>(std::floor(fov_rad / resolution_rad + 1e-6)) + 1;
}

double PlanarScannerSpec::angleMin() const {
  if (std::isfinite(angle_min_rad)) return angle_min_rad;
  return -0.5 * static_cast<double>(numBeams() - 1) * resolution_rad;
}

BeamSet PlanarScannerSpec::beams() const {
  BeamSet b;
  b.range_min = static_cast<float>(range_min);
  b.range_max = static_cast<float>(range_max);
  const size_t n = numBeams();
  const double a0 = angleMin();
  for (size_t i = 0; i < n; ++i) {
    const double a = a0 + static_cast<double>(i) * resolution_rad;
    b.push(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.f);
  }
  return b;
}

PlanarScannerSpec sickS300() { return {deg2rad(270), deg2rad(0.5), 0.05, 30.0, 12.5}; }
PlanarScannerSpec hokuyoURG04LX() { return {deg2rad(240), deg2rad(0.36), 0.02, 4.0, 10.0}; }
PlanarScannerSpec sickLMS200() { return {deg2rad(180), deg2rad(0.5), 0.05, 8.0, 75.0}; }

}  // namespace polyloc
