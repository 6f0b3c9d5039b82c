// Moved points into detections: single-linkage clusters of the points that motion detection
// found (of one scanner or of several at the same time), each summarised by its centroid, the
// spread of its points and their count.
#pragma once

#include <polyloc/tracking/config.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace polyloc {

// A scan endpoint of a moving object (map frame, or odom), with the position of the scanner that
// saw it: a seed lies where there was free space before; the others belong with a seed (the
// other leg of a person, which the earlier scans could not see).
struct MotionPoint {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
  bool seed = true;
};

struct Detection {
  int64_t stamp_ns = 0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();     // centroid, corrected for the surface offset
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  // spread of the points (+ min_sigma^2)
  size_t points = 0;   // all points of the cluster
  size_t seeds = 0;    // of them, seeds
};

// Clusters of points closer than c.distance with at least c.min_points seeds, at most
// c.max_extent across.
// Points that are not finite are skipped.
std::vector<Detection> clusterDetections(std::span<const MotionPoint> points, const ClusterConfig& c,
                                         int64_t stamp_ns);

}  // namespace polyloc
