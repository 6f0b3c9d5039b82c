// The estimate of a particle set: the dominant cluster (8-connected occupied x-y cells, the
// heaviest component), its weighted mean pose and 6x6 covariance (x y z roll pitch yaw), and a
// status from spread and cluster mass.
#pragma once

#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/localizer.hpp>

namespace polyloc {

struct ClusterEstimate {
  Pose pose;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  double mass = 0;       // weight of the dominant cluster (of 1)
  size_t clusters = 0;   // connected components found
};

// logw must be normalised (resample.hpp). cell: cluster grid size in metres.
ClusterEstimate dominantCluster(const ParticleSet& s, double cell);

// Tracking when the dominant cluster holds most of the weight and is tight; Uncertain otherwise.
MclStatus statusOf(const ClusterEstimate& e, const MclConfig& config);

}  // namespace polyloc
