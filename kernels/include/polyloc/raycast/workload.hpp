// Standard ray-casting workloads, shared by `polyloc bench raycast`, the Google Benchmark suite
// and tests, so that every figure is measured on the same rays.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sensors/beams.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace polyloc {

// n beams evenly over 360 deg in the sensor's x-y plane, starting straight ahead.
BeamSet horizontalFan(size_t n, float range_max = 30.f, float range_min = 0.f);

// n poses uniform in the x/y box at height z, yaw uniform in [-pi, pi), from CounterRng(seed).
std::vector<Pose> randomPlanarPoses(const Eigen::AlignedBox3f& bounds, size_t n, double z,
                                    uint64_t seed = 1);

}  // namespace polyloc
