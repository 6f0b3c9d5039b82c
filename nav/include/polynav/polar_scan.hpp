// The range scan local obstacle avoidance reads: one 2D polar scan in base_link, laid out like
// sensor_msgs/LaserScan and polyloc's VRS (beam i along angle_min + i * angle_increment). A range
// above range_max or not finite means nothing in that direction (REP-117; the shared-memory VRS
// writes range_max + 1); one <= 0 is no reading (drivers write 0 for "no return") and is skipped too. For a VRS, whose segment i is centred half an increment further, pass
// angle_min + angle_increment / 2.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace polynav {

struct PolarScan {
  double angle_min = -M_PI;     // rad, base frame, beam 0
  double angle_increment = 0;   // rad between beams, > 0 (counter-clockwise)
  double range_max = 0;         // m
  std::vector<float> ranges;    // m per beam

  size_t size() const { return ranges.size(); }
  double angle(size_t i) const { return angle_min + double(i) * angle_increment; }
  // Something was seen along beam i: a range in (0, range_max].
  bool hit(size_t i) const { return std::isfinite(ranges[i]) && ranges[i] > 0 && ranges[i] <= range_max; }
  double range(size_t i) const { return double(ranges[i]); }
  // Beam i's return in the base frame (meaningful for a hit).
  Eigen::Vector2d point(size_t i) const { return range(i) * Eigen::Vector2d(std::cos(angle(i)), std::sin(angle(i))); }
  // The beams go once around (the last one's neighbour is the first).
  bool fullCircle() const { return double(size()) * angle_increment >= 2 * M_PI - angle_increment / 2; }
  // The beam nearest direction `a` (any multiple of 2 pi apart); none outside the scan's coverage
  // (more than half an increment past its first or last beam) or for `a` not finite.
  std::optional<size_t> indexOf(double a) const {
    if (!std::isfinite(a) || ranges.empty() || !(angle_increment > 0)) return std::nullopt;
    double d = std::remainder(a - angle_min, 2 * M_PI);
    if (d < -angle_increment / 2) d += 2 * M_PI;
    const double i = std::round(d / angle_increment);
    if (i < double(size())) return size_t(std::max(0.0, i));
    if (fullCircle()) return size_t(0);
    return std::nullopt;
  }
  // Throws std::invalid_argument, prefixed with `who`, naming the field: no ranges, angle_min not
  // finite, angle_increment <= 0 or not finite, range_max <= 0 or not finite, beams overlapping
  // beyond a full turn.
  void validate(const std::string& who) const {
    std::ostringstream s;
    if (ranges.empty()) s << "scan.ranges is empty";
    else if (!std::isfinite(angle_min)) s << "scan.angle_min must be finite, got " << angle_min;
    else if (!(angle_increment > 0) || !std::isfinite(angle_increment))
      s << "scan.angle_increment must be > 0 and finite, got " << angle_increment;
    else if (!(range_max > 0) || !std::isfinite(range_max)) s << "scan.range_max must be > 0 and finite, got " << range_max;
    else if (double(size()) * angle_increment > 2 * M_PI + angle_increment / 2)
      s << "scan.angle_increment " << angle_increment << " x " << size() << " ranges exceeds a full turn";
    if (!s.str().empty()) throw std::invalid_argument(who + ": " + s.str());
  }
};

}  // namespace polynav
