// The robot's body as local obstacle avoidance sees it: a rectangle about base_link (x forward,
// y left). A rectangle is not a circle: what keeps the robot off an obstacle is the gap between
// the obstacle and the body, so distances are measured from the hull, not from the centre. An
// obstacle 0.35 m to the side of a 0.5 m wide robot is 0.10 m away, one 0.35 m ahead of a robot
// reaching 0.3 m forward only 0.05 m.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace polynav {

struct RectHull {
  double front = 0.3, rear = 0.3, left = 0.25, right = 0.25;  // m from base_link's origin to each side

  // Distance from the origin to the hull's boundary along direction `theta` (rad, base frame):
  // front at 0, left at pi/2, rear at pi, the corner distance along a corner's direction.
  // NaN for a theta that is not finite.
  double extent(double theta) const;
  // The gap between the body and an obstacle seen at polar (angle, range): range - extent(angle)
  // (negative: the point is inside the hull).
  double clearance(double angle, double range) const { return range - extent(angle); }
  double width() const { return left + right; }  // what must fit through a gap, driving forward
  // Throws std::invalid_argument naming the side that is negative or not finite.
  void validate() const;
  // The bounding rectangle of a footprint polygon (base frame), grown where needed to hold the
  // origin: the extents above only mean something for a hull around base_link. Throws
  // std::invalid_argument for an empty footprint or a vertex that is not finite.
  static RectHull fromFootprint(const std::vector<Eigen::Vector2d>& footprint);
};

}  // namespace polynav
