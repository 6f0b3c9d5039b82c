#include <polyloc/sim/vrs_truth.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace polyloc {

std::vector<float> trueVirtualScan(const RayCaster& map, const PeopleScene& people, const Pose& map_T_base,
                                   const VrsConfig& config, double height_step) {
  if (!(height_step > 0)) throw std::invalid_argument("trueVirtualScan: height_step must be > 0");
  const size_t n = size_t(std::ceil((config.angle_max - config.angle_min) / config.resolution - 1e-9));
  BeamSet fan;
  fan.range_min = 0.f;
  fan.range_max = float(config.range_max);
  for (size_t i = 0; i < n; ++i) {
    const double a = config.angle_min + (double(i) + 0.5) * config.resolution;
    fan.push(float(std::cos(a)), float(std::sin(a)), 0.f);
  }
  // One level fan per height, at the robot's position and heading.
  std::vector<Pose> poses;
  const Eigen::Vector3d up = map_T_base.rotation() * Eigen::Vector3d::UnitZ();
  for (double h = config.floor_clearance + 0.5 * height_step; h <= config.robot_height; h += height_step)
    poses.push_back(Pose::fromXYZRPY(map_T_base.x() + h * up.x(), map_T_base.y() + h * up.y(), map_T_base.z() + h * up.z(),
                                     0, 0, map_T_base.yaw()));
  std::vector<float> hit(poses.size() * n);
  HitBuffers out;
  out.range = hit.data();
  map.castScans(poses, fan, out);
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> ranges(n, inf);
  for (size_t p = 0; p < poses.size(); ++p) {
    const Eigen::Vector3f o = poses[p].translation().cast<float>();
    for (size_t i = 0; i < n; ++i) {
      float r = hit[p * n + i];
      if (!people.empty()) {
        const Eigen::Vector3f d = (poses[p].rotation() * Eigen::Vector3d(fan.dx[i], fan.dy[i], 0)).cast<float>();
        r = std::min(r, people.intersect(o, d, 0.f, std::isfinite(r) ? r : fan.range_max, nullptr));
      }
      if (r <= fan.range_max) ranges[i] = std::min(ranges[i], r);
    }
  }
  return ranges;
}

VrsError compareVirtualScan(std::span<const float> vrs, std::span<const uint8_t> source, std::span<const float> truth,
                            double range_max, double reach) {
  VrsError e;
  double sum2 = 0, sum = 0;
  for (size_t i = 0; i < std::min(vrs.size(), truth.size()); ++i) {
    if (!(truth[i] <= reach)) continue;
    if (i < source.size() && source[i] == kVrsDanger) continue;
    const double d = std::min<double>(std::isfinite(vrs[i]) ? vrs[i] : range_max, range_max) - truth[i];
    sum2 += d * d, sum += std::abs(d), ++e.segments;
    e.missed += d > 0.1;
  }
  if (e.segments) e.rmse_m = std::sqrt(sum2 / double(e.segments)), e.mean_abs_m = sum / double(e.segments);
  return e;
}

}  // namespace polyloc
