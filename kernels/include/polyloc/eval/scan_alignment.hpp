// The floor of a real-log evaluation: where one scan fits the map best near a known pose, found
// by exhaustive search over a small x, y, yaw window (mcl/pose_search.hpp: truncated squared
// range residuals of all valid beams), then point-to-plane refinement against the mesh
// (mcl/refine.hpp) from the best cell. The distance between the fitted and the known pose is the
// error that the map itself allows a localiser (map error plus ground-truth error): a localiser
// that matches scans to this map cannot be expected to come closer to the known poses.
//
//   ScanAlignment a = alignScan(caster, rig, 0, ranges, known_pose);
//   a.pose, a.rms_m, a.inliers
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/config.hpp>
#include <polyloc/mcl/pose_search.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/sensors/rig.hpp>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace polyloc {

struct AlignmentSearch {
  PoseSearch search{0.10, 0.0349065850398866, 0.05, 0.0174532925199433, 0.10, 0, 0.05};  // +-10 cm, +-2 deg, all beams
  RefineConfig refine;                      // the refinement after the search (all beams, dof 3)
  AlignmentSearch() {
    refine.beams_per_scan = 0;
    refine.search_xy = refine.search_yaw = 0;  // the search above
    refine.max_correction = 0.15;
    refine.min_inlier_ratio = 0.3;
  }
};

struct ScanAlignment {
  Pose pose;            // the best fit (the search's best cell when the refinement is refused)
  bool refined = false; // the refinement was accepted
  std::string refine_reason;  // why not ("" when accepted)
  double rms_m = 0;     // RMS point-to-plane residual of the refinement's inliers
  // Position std (m) along the scanner's heading and across it, from the refinement's covariance:
  // in a corridor the scan leaves the position along it open (large along, small across).
  double std_along = 0, std_across = 0;
  size_t inliers = 0, beams = 0;
};

// ranges: the sensor's beams in order (invalid ones skipped). Runs its casts on the caller's
// threads (castScans of the caster). The map's range bias (mcl.range_bias: walls proud of the
// surfaces) is the caller's: take it off the ranges first (rangeBiasAt, mcl/refine.hpp's
// subtractRangeBias).
ScanAlignment alignScan(const RayCaster& caster, const Rig& rig, size_t sensor, std::span<const float> ranges,
                        const Pose& map_T_base, const AlignmentSearch& search = {});

// The range bias of one scan at a known pose (the refinement with refine.range_bias from there;
// NaN when refused): the median over a run's scans is the map's.
double rangeBiasAt(const RayCaster& caster, const Rig& rig, size_t sensor, std::span<const float> ranges,
                   const Pose& map_T_base);

}  // namespace polyloc
