#include <polyloc/geometry/domain.hpp>

#include <cmath>
#include <fmt/format.h>

namespace polyloc::domain {

namespace {
std::string number(double v) { return fmt::format("{:g}", v); }

std::optional<std::string> outside(const char* name, double v, double lo, double hi) {
  if (!std::isfinite(v)) return fmt::format("{} is {}: not a finite number", name, number(v));
  if (v < lo || v > hi)
    return fmt::format("{} is {}: outside the map's area plus {} m", name, number(v), kMapMargin);
  return std::nullopt;
}
}  // namespace

std::optional<std::string> checkValue(const char* name, double v, double limit) {
  if (!std::isfinite(v)) return fmt::format("{} is {}: not a finite number", name, number(v));
  if (std::abs(v) > limit) return fmt::format("{} is {}: beyond +-{}", name, number(v), number(limit));
  return std::nullopt;
}

std::optional<std::string> checkPose(const Pose& p) {
  static const char* kAxes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    if (auto why = checkValue(kAxes[k], p.translation()[k], kMaxCoordinate)) return why;
  const Eigen::Vector4d q = p.rotation().coeffs();
  if (!q.allFinite() || std::abs(q.norm() - 1.0) > 1e-3) return std::string("rotation is not a unit quaternion");
  return std::nullopt;
}

std::optional<std::string> checkPose(const Pose& p, const Eigen::AlignedBox3f& map) {
  if (auto why = checkPose(p)) return why;
  static const char* kAxes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    if (auto why = outside(kAxes[k], p.translation()[k], double(map.min()[k]) - kMapMargin,
                           double(map.max()[k]) + kMapMargin))
      return why;
  return std::nullopt;
}

std::optional<std::string> checkPlanar(double x, double y, double yaw, const Eigen::AlignedBox3f& map) {
  if (auto why = outside("x", x, double(map.min().x()) - kMapMargin, double(map.max().x()) + kMapMargin)) return why;
  if (auto why = outside("y", y, double(map.min().y()) - kMapMargin, double(map.max().y()) + kMapMargin)) return why;
  return checkValue("yaw", yaw, kMaxAngle);
}

std::optional<std::string> checkSpread(const char* name, double v, double limit) {
  if (!std::isfinite(v)) return fmt::format("{} is {}: not a finite number", name, number(v));
  if (v < 0 || v > limit) return fmt::format("{} is {}: outside 0 .. {}", name, number(v), number(limit));
  return std::nullopt;
}

std::string describeArea(const Eigen::AlignedBox3f& map) {
  return fmt::format("x {:.1f} .. {:.1f}, y {:.1f} .. {:.1f}", map.min().x() - kMapMargin,
                     map.max().x() + kMapMargin, map.min().y() - kMapMargin, map.max().y() + kMapMargin);
}

}  // namespace polyloc::domain
