// What the controller asks of a scan (the VRS, base_link): obstacle points in the map frame, the
// danger zones added as virtual obstacles (so local avoidance stops before them even when the scan
// does not show them), the free distance straight ahead of the hull, and whether a path ahead is
// obstructed.
#pragma once

#include <polynav/hull.hpp>
#include <polynav/polar_scan.hpp>
#include <polynav/zones.hpp>

#include <Eigen/Core>
#include <vector>

namespace polynav {

// The scan's obstacle points (ranges within range_max) in the map frame, robot at pose (x, y, yaw).
std::vector<Eigen::Vector2d> scanPoints(const PolarScan& scan, const Eigen::Vector3d& pose);

// Each beam shortened to where it meets a polygon's edge (map frame polygons, robot at pose).
void addPolygons(PolarScan& scan, const std::vector<Polygon>& polygons, const Eigen::Vector3d& pose);

// Free distance (m) the hull can move straight forward (backward for a negative direction)
// before touching a scan point: points beside the hull's sides do not count.
double freeTravel(const PolarScan& scan, const RectHull& hull, bool forward = true);

// Whether turning the hull in place by `angle` (rad, signed: counter-clockwise > 0) keeps it
// `margin` clear of every scan point: the corners of a rectangle sweep a circle wider than its sides.
bool rotationClear(const PolarScan& scan, const RectHull& hull, double angle, double margin = 0.02);

// The arc length (from the path's progress point) of the first scan point (map frame) closer than
// `radius` to the path within `ahead_m`, or a negative value when none is.
double obstructedAt(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& path,
                    size_t from_segment, double ahead_m, double radius, Eigen::Vector2d* where = nullptr);

}  // namespace polynav
