// Helpers of the tracking tests: scans of a planar scanner in a 2D scene of axis-aligned boxes
// (walls, pillars, a moving "person"), cast analytically, so the tests need no map or caster.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/planar_scanner.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

namespace polyloc::test {

struct Scene2D {
  std::vector<Eigen::AlignedBox2d> boxes;
  // A closed room [-hx, hx] x [-hy, hy] inside walls 0.2 m thick.
  static Scene2D room(double hx, double hy) {
    Scene2D s;
    s.boxes.push_back({Eigen::Vector2d(-hx - 0.2, -hy - 0.2), Eigen::Vector2d(hx + 0.2, -hy)});
    s.boxes.push_back({Eigen::Vector2d(-hx - 0.2, hy), Eigen::Vector2d(hx + 0.2, hy + 0.2)});
    s.boxes.push_back({Eigen::Vector2d(-hx - 0.2, -hy), Eigen::Vector2d(-hx, hy)});
    s.boxes.push_back({Eigen::Vector2d(hx, -hy), Eigen::Vector2d(hx + 0.2, hy)});
    return s;
  }
  Scene2D with(const Eigen::Vector2d& centre, double half) const {
    Scene2D s = *this;
    s.boxes.push_back({centre - Eigen::Vector2d(half, half), centre + Eigen::Vector2d(half, half)});
    return s;
  }
};

// Nearest entry of the ray o + t d (t > 0) into a box, +inf for none.
inline double rayBox(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const Eigen::AlignedBox2d& b) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < b.min()[k] || o[k] > b.max()[k]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double a = (b.min()[k] - o[k]) / d[k], c = (b.max()[k] - o[k]) / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a), t1 = std::min(t1, c);
  }
  return t0 <= t1 && t0 > 0 ? t0 : std::numeric_limits<double>::infinity();
}

// Ranges of `spec` at a level pose, +inf beyond range_max (no noise).
inline std::vector<float> scan2d(const PlanarScannerSpec& spec, const Pose& map_T_sensor, const Scene2D& scene) {
  std::vector<float> r(spec.numBeams());
  const Eigen::Vector2d o(map_T_sensor.x(), map_T_sensor.y());
  for (size_t i = 0; i < r.size(); ++i) {
    const double a = map_T_sensor.yaw() + spec.angleMin() + double(i) * spec.resolution_rad;
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& b : scene.boxes) best = std::min(best, rayBox(o, d, b));
    r[i] = best <= spec.range_max ? float(best) : std::numeric_limits<float>::infinity();
  }
  return r;
}

inline constexpr int64_t kTestStep = 80'000'000;  // ns between scans (12.5 Hz)

}  // namespace polyloc::test
