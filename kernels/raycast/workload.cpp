#include <polyloc/geometry/random.hpp>
#include <polyloc/raycast/workload.hpp>

#include <cmath>

namespace polyloc {

BeamSet horizontalFan(size_t n, float range_max, float range_min) {
  BeamSet b;
  b.range_min = range_min;
  b.range_max = range_max;
  for (size_t i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n);
    b.push(static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a)), 0.f);
  }
  return b;
}

std::vector<Pose> randomPlanarPoses(const Eigen::AlignedBox3f& bounds, size_t n, double z,
                                    uint64_t seed) {
  const CounterRng rng(seed);
  std::vector<Pose> poses;
  poses.reserve(n);
  for (size_t i = 0; i < n; ++i)
    poses.push_back(Pose::fromXYZRPY(rng.uniform(bounds.min().x(), bounds.max().x(), 0, i, 0),
                                     rng.uniform(bounds.min().y(), bounds.max().y(), 0, i, 1), z, 0,
                                     0, rng.uniform(-M_PI, M_PI, 0, i, 2)));
  return poses;
}

}  // namespace polyloc
