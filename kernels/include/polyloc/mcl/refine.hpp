// Local refinement of an MCL estimate against the mesh, as MICP-L does: point-to-plane
// Gauss-Newton on ray-cast correspondences. For each valid beam the ray is cast in the map from
// the sensor at the current pose; the hit q with its triangle normal n is the correspondence of
// the measured endpoint p (same ray, measured range), residual n . (p - q). Huber-weighted
// normal equations give the step; correspondences are re-cast every iteration. Correspondences
// with |residual| > max_correspondence (people, chairs not in the map) are dropped.
//
// Pose perturbation: translation delta in map axes, rotation about the base origin in map axes
// (R' = Exp(phi) R). With dof 3 only x, y and the rotation about map z move, so z, roll and pitch
// stay exactly as given (Rz(d) Rz(yaw) Ry Rx keeps roll and pitch).
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <Eigen/Core>

#include <span>
#include <string>
#include <vector>

namespace polyloc {

// RefineConfig: polyloc/mcl/config.hpp (mcl.refine).

// One scan of one rig sensor. base_T_base_at_scan: odometry from the reference time (the time of
// map_T_base) to the scan's stamp, identity when the scan was taken at the reference time.
// ranges: along each beam's ray in the sensor's beam order, as Localizer::addScan takes them (a
// ToF camera's depth must be divided by its depthFactors() first).
struct RefineScan {
  size_t sensor = 0;
  std::span<const float> ranges;
  Pose base_T_base_at_scan;
};

struct RefineResult {
  Pose pose;  // refined map_T_base, or the input when not accepted
  // x y z roll pitch yaw; (J^T W J)^-1 times the residual variance. Directions the scans do not
  // observe (along a corridor) show as large variance; held axes (dof 3) are 0.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  size_t correspondences = 0;  // inliers in the last iteration
  size_t beams = 0;            // beams selected from the scans (the inlier ratio's denominator)
  double rms = 0;              // m, RMS point-to-plane residual of the inliers
  int iterations = 0;
  bool accepted = false;
  double range_bias = 0;       // m, estimated with config.range_bias (else 0): add it to the bias applied
  double range_bias_std = 0;   // m
  // (x, y, yaw, map axes) the pose search's likelihood spread about its best candidate
  // (PoseSearchResult::spread); zero without a search or spread_beams.
  Eigen::Matrix3d search_spread = Eigen::Matrix3d::Zero();
  std::string reason;  // why not accepted ("" when accepted)
};

// Ranges less a range bias (refine.range_bias, mcl.range_bias): the valid ones (finite, below
// range_max) only, never below 0; into `out` (resized).
void subtractRangeBias(std::span<const float> ranges, double bias, float range_max, std::vector<float>& out);

// scans: the latest scan of each sensor (any subset of the rig; one sensor may appear twice).
// dof: 3 (x, y, yaw) or 6. Throws std::invalid_argument for a bad sensor index or dof.
// spread_beams: the search's beams counted as this many for its spread (0: none computed).
RefineResult refinePose(const RayCaster& caster, const Rig& rig, std::span<const RefineScan> scans,
                        const Pose& map_T_base, int dof, const RefineConfig& config, double spread_beams = 0);

}  // namespace polyloc
