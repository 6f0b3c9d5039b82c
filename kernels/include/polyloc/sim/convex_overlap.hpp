// Exact overlap of two convex shapes by the separating axis theorem: the shapes are disjoint
// exactly when their projections onto some face normal of either shape, or onto the cross
// product of an edge of one with an edge of the other, do not meet. Shapes are closed sets:
// touching (a shared point, edge or face) counts as overlap, up to floating-point rounding.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace polyloc {

// A convex polytope (or a flat convex polygon in 3D) as SAT needs it. Normals and edge
// directions need not be unit length; a direction and its negation are one axis, give either.
struct ConvexShape {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3d> face_normals;
  std::vector<Eigen::Vector3d> edge_dirs;

  // Triangle a, b, c: flat, one normal, three edges.
  static ConvexShape triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);
  // Box with the given centre, orientation (columns: the box axes) and half extents.
  static ConvexShape box(const Eigen::Vector3d& centre, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& half);
  // Convex polygon (either winding) turned by yaw about z and shifted by origin, extruded
  // vertically from z0 to z1.
  static ConvexShape prism(const std::vector<Eigen::Vector2d>& convex_polygon, double z0, double z1,
                           const Eigen::Vector2d& origin, double yaw);
};

// True when a and b share at least one point.
bool overlap(const ConvexShape& a, const ConvexShape& b);

// A simple polygon (either winding, at least 3 points) as convex pieces: itself when convex,
// else its ear-clipping triangles, all counter-clockwise. Collinear points are dropped. Throws
// std::invalid_argument when the polygon has no area or is not simple (no ear found).
std::vector<std::vector<Eigen::Vector2d>> convexPieces(const std::vector<Eigen::Vector2d>& polygon);

}  // namespace polyloc
