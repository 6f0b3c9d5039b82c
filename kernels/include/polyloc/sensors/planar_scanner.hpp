// 2D laser scanner (SICK S300/LMS200, Hokuyo URG): beams fanned in the sensor's x-y plane,
// counter-clockwise from -fov/2 to +fov/2 as in sensor_msgs/LaserScan. Mount it tilted
// (pitch/roll in the mount pose) for the thesis's funnel of tilted scanners.
#pragma once

#include <polyloc/sensors/beams.hpp>

#include <limits>

namespace polyloc {

struct PlanarScannerSpec {
  double fov_rad = 4.71238898038469;        // 270 deg
  double resolution_rad = 0.00872664625997;  // 0.5 deg
  double range_min = 0.05;
  double range_max = 30.0;
  double rate_hz = 12.5;
  // Angle of the first beam; NaN: the beams are centred on the x axis. A recorded scan need not
  // be centred (a CARMEN FLASER's 180 beams span -90..+89 deg).
  double angle_min_rad = std::numeric_limits<double>::quiet_NaN();
  // The geometry (fov, resolution, angle_min, ranges) is taken from the first scan on the
  // sensor's topic in the recording (rig preset `recorded`, io/recorded_geometry.hpp).
  bool from_recording = false;

  size_t numBeams() const;     // floor(fov / resolution) + 1
  double angleMin() const;     // angle of the first beam (radians, about z)
  BeamSet beams() const;
};

PlanarScannerSpec sickS300();     // 270 deg, 0.5 deg, 30 m, 12.5 Hz (541 beams)
PlanarScannerSpec hokuyoURG04LX();  // 240 deg, 0.36 deg, 4 m, 10 Hz (667 beams)
PlanarScannerSpec sickLMS200();   // 180 deg, 0.5 deg, 8 m, 75 Hz (361 beams)

}  // namespace polyloc
