// The documented domain of every numeric value that enters polyloc (docs/failure.md): a value
// outside it is refused with the reason these checks return, and counted, before any kernel sees
// it. Finite is not enough: 1e19 m is finite, yet as a ray origin it aborts Embree, and as a
// pose it puts every particle where no map is.
//
//   if (auto why = domain::checkPose(p, map.bounds())) reject(*why);   // "x is 1e+19: ..."
#pragma once

#include <polyloc/geometry/domain_limits.hpp>
#include <polyloc/geometry/pose.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>

namespace polyloc::domain {

// Empty when v is finite and |v| <= limit; else "NAME is VALUE: REASON".
std::optional<std::string> checkValue(const char* name, double v, double limit);
// Finite, unit-norm rotation, |coordinate| <= kMaxCoordinate.
std::optional<std::string> checkPose(const Pose& p);
// The one rule for "a usable pose" wherever poses are filtered (ground truth, VRS, pipeline).
inline bool validPose(const Pose& p) { return !checkPose(p).has_value(); }
// As checkPose, and inside `map` grown by kMapMargin in every direction.
std::optional<std::string> checkPose(const Pose& p, const Eigen::AlignedBox3f& map);
// x, y, yaw as a user types them; the point must be inside the map's box (plus margin) in x, y.
std::optional<std::string> checkPlanar(double x, double y, double yaw, const Eigen::AlignedBox3f& map);
// A spread: finite, >= 0, <= limit.
std::optional<std::string> checkSpread(const char* name, double v, double limit);

// The map's box grown by kMapMargin, as "[x0, x1] x [y0, y1]" for messages.
std::string describeArea(const Eigen::AlignedBox3f& map);

}  // namespace polyloc::domain
