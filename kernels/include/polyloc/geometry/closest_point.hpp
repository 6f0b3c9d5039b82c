// Closest point on a triangle to a point (Ericson, Real-Time Collision Detection, 5.1.5).
// Used for clearance queries ("at least r away from any surface").
#pragma once

#include <Eigen/Core>

namespace polyloc {

Eigen::Vector3f closestPointOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                                       const Eigen::Vector3f& b, const Eigen::Vector3f& c);
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace polyloc
