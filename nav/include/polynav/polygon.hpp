// Polygon tools: any simple polygon (no self-crossing), possibly non-convex, either winding, the
// last point joined to the first. Coordinates in metres; every function is deterministic.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace polynav {

using Polygon = std::vector<Eigen::Vector2d>;

// Winding number; points on the boundary count as inside.
bool pointInPolygon(const Polygon& poly, const Eigen::Vector2d& p);
// 0 inside or on the boundary, else the distance to the nearest edge.
double polygonDistance(const Polygon& poly, const Eigen::Vector2d& p);
// Whether two polygons share any point (edges crossing or touching, or one inside the other).
bool polygonsOverlap(const Polygon& a, const Polygon& b);
// `footprint` (base_link x/y) placed at pose (x, y, yaw).
Polygon placeFootprint(const Polygon& footprint, const Eigen::Vector3d& pose);
// "" for a simple polygon with area, else what is wrong ("has 2 points, needs at least 3",
// "point 3 is not finite", "points 2 and 3 coincide", "edges 0 and 2 cross", "has no area").
std::string polygonProblem(const Polygon& poly);

}  // namespace polynav
