#include <polyloc/config/robot.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc {

namespace {
double signedArea(const std::vector<Eigen::Vector2d>& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& u = p[i];
    const Eigen::Vector2d& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return 0.5 * a;
}
}  // namespace

const char* kinematicsName(Kinematics k) {
  return k == Kinematics::Omni ? "omni" : "differential";
}

double RobotSpec::boundingRadius() const {
  if (footprint.empty()) return radius;
  double r = 0;
  for (const auto& p : footprint) r = std::max(r, p.norm());
  return r;
}

double RobotSpec::inscribedRadius() const {
  if (footprint.empty()) return radius;
  double r = INFINITY;
  bool inside = false;  // crossing number of a ray from the origin along +x
  for (size_t i = 0; i < footprint.size(); ++i) {
    const Eigen::Vector2d a = footprint[i], b = footprint[(i + 1) % footprint.size()];
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp(-a.dot(ab) / std::max(ab.squaredNorm(), 1e-18), 0.0, 1.0);
    r = std::min(r, (a + t * ab).norm());
    if ((a.y() > 0) != (b.y() > 0) && a.x() + (0 - a.y()) * ab.x() / ab.y() > 0) inside = !inside;
  }
  return inside ? r : 0.0;
}

std::vector<Eigen::Vector2d> RobotSpec::outline(double spacing) const {
  std::vector<Eigen::Vector2d> out;
  if (footprint.empty()) {
    const int n = std::max(8, static_cast<int>(std::ceil(2 * M_PI * radius / spacing)));
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      out.emplace_back(radius * std::cos(a), radius * std::sin(a));
    }
    return out;
  }
  for (size_t i = 0; i < footprint.size(); ++i) {
    const Eigen::Vector2d a = footprint[i], b = footprint[(i + 1) % footprint.size()];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
  }
  return out;
}

std::vector<Eigen::Vector2d> RobotSpec::contactPoints() const {
  if (!footprint.empty()) return footprint;
  const double r = 0.8 * radius;
  return {{r, 0}, {0, r}, {-r, 0}, {0, -r}};
}

RobotSpec parseRobot(ConfigMap m) {
  RobotSpec r;
  if (m.has("footprint") && m.has("radius"))
    m.fail("give either footprint (a polygon) or radius (round), not both");
  if (m.has("footprint")) {
    const ConfigValue v = m.value("footprint");
    for (const ConfigValue& p : v.items()) {
      const std::vector<double> xy = p.asDoubles(2);
      r.footprint.emplace_back(xy[0], xy[1]);
    }
    if (r.footprint.size() < 3) v.fail("a footprint polygon needs at least 3 points");
    const double area = signedArea(r.footprint);
    if (std::abs(area) < 1e-4) v.fail("the footprint polygon has no area");
    if (area < 0) std::reverse(r.footprint.begin(), r.footprint.end());  // counter-clockwise
  }
  r.radius = m.getDouble("radius", r.radius, 0.01, 10.0);
  r.height = m.getDouble("height", r.height, 0.05, 10.0);
  r.kinematics = m.getChoice("kinematics", "differential", {"differential", "omni"}) == "omni"
                     ? Kinematics::Omni
                     : Kinematics::Differential;
  m.finish();
  return r;
}

}  // namespace polyloc
