#include <polyloc/eval/ground_truth.hpp>
#include <polyloc/geometry/domain.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc {

GroundTruth::GroundTruth(std::vector<StampedPose> poses, double max_gap_s)
    : max_gap_ns_(static_cast<int64_t>(std::llround(max_gap_s * 1e9))) {
  const size_t given = poses.size();
  std::erase_if(poses, [](const StampedPose& p) { return !domain::validPose(p.pose); });
  // Stable: of two poses with one stamp the first in the file wins, as a reader would expect.
  std::stable_sort(poses.begin(), poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.stamp_ns < b.stamp_ns; });
  poses.erase(std::unique(poses.begin(), poses.end(),
                          [](const StampedPose& a, const StampedPose& b) { return a.stamp_ns == b.stamp_ns; }),
              poses.end());
  dropped_ = given - poses.size();
  poses_ = std::move(poses);
}

std::optional<Pose> GroundTruth::at(int64_t stamp_ns) const {
  if (poses_.empty() || stamp_ns < poses_.front().stamp_ns || stamp_ns > poses_.back().stamp_ns) return std::nullopt;
  auto hi = std::lower_bound(poses_.begin(), poses_.end(), stamp_ns,
                             [](const StampedPose& p, int64_t t) { return p.stamp_ns < t; });
  if (hi->stamp_ns == stamp_ns) return hi->pose;
  const auto lo = std::prev(hi);  // exists: stamp_ns > front
  const int64_t span = hi->stamp_ns - lo->stamp_ns;
  if (span > max_gap_ns_) return std::nullopt;
  const double s = static_cast<double>(stamp_ns - lo->stamp_ns) / static_cast<double>(span);
  return Pose::interpolate(lo->pose, hi->pose, s);
}

}  // namespace polyloc
