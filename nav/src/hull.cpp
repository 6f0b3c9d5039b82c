#include <polynav/hull.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace polynav {

double RectHull::extent(double theta) const {
  if (!std::isfinite(theta)) return std::numeric_limits<double>::quiet_NaN();
  const double c = std::cos(theta), s = std::sin(theta);
  // The ray leaves the rectangle through whichever side it reaches first.
  double t = std::numeric_limits<double>::infinity();
  if (c > 0) t = std::min(t, front / c);
  else if (c < 0) t = std::min(t, rear / -c);
  if (s > 0) t = std::min(t, left / s);
  else if (s < 0) t = std::min(t, right / -s);
  return t;
}

void RectHull::validate() const {
  const std::pair<const char*, double> sides[] = {{"front", front}, {"rear", rear}, {"left", left}, {"right", right}};
  for (const auto& [name, value] : sides)
    if (!(value >= 0) || !std::isfinite(value)) {
      std::ostringstream s;
      s << "RectHull: " << name << " must be finite and >= 0, got " << value;
      throw std::invalid_argument(s.str());
    }
}

RectHull RectHull::fromFootprint(const std::vector<Eigen::Vector2d>& footprint) {
  if (footprint.empty()) throw std::invalid_argument("RectHull::fromFootprint: footprint is empty");
  // Starting from the origin grows the rectangle to hold it.
  RectHull h{0, 0, 0, 0};
  for (size_t i = 0; i < footprint.size(); ++i) {
    const Eigen::Vector2d& p = footprint[i];
    if (!p.allFinite()) {
      std::ostringstream s;
      s << "RectHull::fromFootprint: footprint vertex " << i << " is not finite: (" << p.x() << ", " << p.y() << ")";
      throw std::invalid_argument(s.str());
    }
    h.front = std::max(h.front, p.x());
    h.rear = std::max(h.rear, -p.x());
    h.left = std::max(h.left, p.y());
    h.right = std::max(h.right, -p.y());
  }
  return h;
}

}  // namespace polynav
