// Line segments of one 2D scan (split-and-merge): the first stage of the plane-fragment model.
// The scan is cut where consecutive points lie farther apart than max_gap (object edges,
// invalid beams in between), each run is split recursively at the point farthest from its
// chord while that exceeds split_threshold, neighbours that fit one line are merged again, and
// every segment is refitted by total least squares (the fit is isotropic: no axis is special).
#pragma once

#include <polyloc/sensors/beams.hpp>

#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

namespace polyloc {

struct LineFitParams {
  double split_threshold = 0.03;  // m
  size_t min_points = 8;
  double min_length = 0.2;        // m
  double max_gap = 0.2;           // m
};

// A fitted segment. Endpoints are the first and last point projected onto the fitted line, so
// b - a is parallel to dir (unit, from a to b).
struct LineSegment {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  Eigen::Vector3d dir = Eigen::Vector3d::UnitX();
  size_t points = 0;
  double rms = 0;  // m, orthogonal distances of the points to the line

  double length() const { return (b - a).norm(); }
};

// Segments of a scan in the sensor frame (the scan plane: z = 0 for a planar scanner's beams).
// ranges: one per beam of `beams`; NaN, inf and ranges outside [range_min, range_max) are skipped.
std::vector<LineSegment> fitLineSegments(std::span<const float> ranges, const BeamSet& beams,
                                         const LineFitParams& params = {});

// Total-least-squares line through the points (in their order): the segment, its rms and count.
LineSegment fitLine(std::span<const Eigen::Vector3d> points);

}  // namespace polyloc
