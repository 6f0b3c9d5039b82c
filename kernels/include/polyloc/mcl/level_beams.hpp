// Level beams: those within about 10 deg of horizontal in the map frame. On a flat floor a beam
// that hits the floor reads the same at every x, y and heading, so only level beams tell places
// apart: the fit check compares them alone (with the tilted scanners' floor hits 8 of 20
// simulated kidnaps were never contradicted), and the pose search scores them alone (a tilted
// scanner's floor hits cost rays and decide nothing).
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace polyloc {

inline constexpr double kLevelElevationSin = 0.17;  // ~10 deg

inline bool isLevelRay(const Eigen::Vector3d& dir_map) {
  return std::abs(dir_map.z()) <= kLevelElevationSin * dir_map.norm();
}

}  // namespace polyloc
