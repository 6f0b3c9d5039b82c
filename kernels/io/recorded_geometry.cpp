#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/recorded_geometry.hpp>

#include <fmt/core.h>

#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {

std::string describe(size_t n, double first, double step) {
  return fmt::format("{} beams, {:.2f}..{:.2f} deg, step {:.3f} deg", n, rad2deg(first),
                     rad2deg(first + step * double(n > 0 ? n - 1 : 0)), rad2deg(step));
}

}  // namespace

PlanarScannerSpec planarSpecFromScan(const msg::LaserScan& s, double rate_hz) {
  const size_t n = s.ranges.size();
  if (n < 2) throw std::invalid_argument(fmt::format("a recorded scan of {} beams has no geometry", n));
  if (!(std::isfinite(s.angle_min) && std::isfinite(s.angle_increment) && s.angle_increment > 0))
    throw std::invalid_argument(fmt::format("recorded scan geometry angle_min {} increment {}: not usable", s.angle_min,
                                            s.angle_increment));
  if (!(s.range_max > s.range_min && s.range_min >= 0 && std::isfinite(s.range_max)))
    throw std::invalid_argument(fmt::format("recorded scan ranges {}..{} m: not usable", s.range_min, s.range_max));
  PlanarScannerSpec p;
  p.resolution_rad = double(s.angle_increment);
  p.fov_rad = p.resolution_rad * double(n - 1);
  p.angle_min_rad = double(s.angle_min);
  p.range_min = double(s.range_min);
  p.range_max = double(s.range_max);
  if (rate_hz > 0) p.rate_hz = rate_hz;
  return p;
}

std::string describeGeometry(const msg::LaserScan& s) {
  return describe(s.ranges.size(), s.angle_min, s.angle_increment);
}

std::string describeGeometry(const PlanarScannerSpec& p) {
  return describe(p.numBeams(), p.angleMin(), p.resolution_rad);
}

std::string geometryMismatch(const Sensor& sensor, const msg::LaserScan& s, double tolerance) {
  const auto* p = std::get_if<PlanarScannerSpec>(&sensor.spec);
  if (!p) return {};  // lidars and cameras are checked by their beam count only
  const size_t n = s.ranges.size(), m = p->numBeams();
  const double first = s.angle_min, last = first + double(s.angle_increment) * double(n > 0 ? n - 1 : 0);
  const double sfirst = p->angleMin(), slast = sfirst + p->resolution_rad * double(m - 1);
  if (n == m && std::abs(first - sfirst) <= tolerance && std::abs(last - slast) <= tolerance) return {};
  return fmt::format("{} recorded, sensor '{}' has {}", describeGeometry(s), sensor.name, describeGeometry(*p));
}

}  // namespace polyloc
