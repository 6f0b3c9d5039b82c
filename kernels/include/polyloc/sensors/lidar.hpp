// Multi-layer spinning lidar (Velodyne VLP-16 and alike): one full revolution as a beam set,
// layer-major (all azimuths of layer 0, then layer 1, ...).
#pragma once

#include <polyloc/sensors/beams.hpp>

#include <vector>

namespace polyloc {

struct LidarSpec {
  std::vector<double> elevations_rad;            // one per layer, angle above the x-y plane
  double azimuth_resolution_rad = 0.00349065850;  // 0.2 deg
  double range_min = 0.4;
  double range_max = 100.0;
  double rate_hz = 10.0;

  size_t numAzimuths() const;  // round(2 pi / resolution)
  size_t numBeams() const { return elevations_rad.size() * numAzimuths(); }
  BeamSet beams() const;
};

LidarSpec velodyneVLP16();  // 16 layers -15..+15 deg in 2 deg steps, 0.2 deg, 100 m, 10 Hz

}  // namespace polyloc
