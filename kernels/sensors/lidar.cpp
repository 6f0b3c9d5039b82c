#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/lidar.hpp>

#include <cmath>

namespace polyloc {

size_t LidarSpec::numAzimuths() const {
  return static_cast<size_t>(std::lround(2.0 * M_PI / azimuth_resolution_rad));
}

BeamSet LidarSpec::beams() const {
  BeamSet b;
  b.range_min = static_cast<float>(range_min);
  b.range_max = static_cast<float>(range_max);
  const size_t na = numAzimuths();
  for (double el : elevations_rad) {
    const double ce = std::cos(el), se = std::sin(el);
    for (size_t i = 0; i < na; ++i) {
      const double az = static_cast<double>(i) * 2.0 * M_PI / static_cast<double>(na);
      b.push(static_cast<float>(ce * std::cos(az)), static_cast<float>(ce * std::sin(az)),
             static_cast<float>(se));
    }
  }
  return b;
}

LidarSpec velodyneVLP16() {
  LidarSpec s;
  for (int i = 0; i < 16; ++i) s.elevations_rad.push_back(deg2rad(-15.0 + 2.0 * i));
  return s;
}

}  // namespace polyloc
