// The limits of the input domain (docs/failure.md), without dependencies: the shared-memory
// library (libc only) checks frames against them too. The checks are in domain.hpp.
#pragma once

#include <cstdint>

namespace polyloc::domain {

// Any coordinate (odometry, poses before a map is known): a building is not 1000 km wide, and
// float rays keep centimetres only well inside this.
inline constexpr double kMaxCoordinate = 1e6;          // m
// A pose in the map may lie this far outside the map's bounding box (a robot just outside a
// scanned area); beyond it there is nothing to localise against.
inline constexpr double kMapMargin = 10.0;             // m
inline constexpr double kMaxAngle = 100.0;             // rad; any angle (yaw, roll, pitch, spreads)
inline constexpr double kMaxPositionSigma = 1000.0;    // m; an initial spread
inline constexpr double kMaxRange = 1e4;               // m; a range reading, a range limit

}  // namespace polyloc::domain
