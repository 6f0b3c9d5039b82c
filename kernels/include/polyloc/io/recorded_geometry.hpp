// A planar scanner's geometry as a recording gives it (sensor_msgs/LaserScan: angle_min,
// angle_increment, the number of ranges, range_min/max), compared with or adopted by a rig
// sensor. A recorded scan need not be centred: a CARMEN FLASER's 180 beams span -90..+89 deg,
// where a centred sensor of 179 deg would span -89.5..+89.5 deg.
#pragma once

#include <polyloc/io/messages.hpp>
#include <polyloc/sensors/sensor.hpp>

#include <string>

namespace polyloc {

// The spec whose beams are the scan's: fov (n - 1) x increment, angle_min as recorded. Ranges:
// the scan's range_min, and its range_max. Throws std::invalid_argument when the geometry is not
// usable (no ranges, a non-finite or non-positive increment, range_max <= range_min).
PlanarScannerSpec planarSpecFromScan(const msg::LaserScan& scan, double rate_hz = 0);

// "180 beams, -90.00..89.00 deg, step 1.000 deg"
std::string describeGeometry(const msg::LaserScan& scan);
std::string describeGeometry(const PlanarScannerSpec& spec);

// Empty when the scan's beams are the sensor's (same count, first and last beam within
// `tolerance` rad); else what differs, naming both, e.g. "180 beams, -90.00..89.00 deg, step
// 1.000 deg recorded, sensor 'laser' has 180 beams, -89.50..89.50 deg, step 1.000 deg".
std::string geometryMismatch(const Sensor& sensor, const msg::LaserScan& scan, double tolerance = 1e-4);

}  // namespace polyloc
