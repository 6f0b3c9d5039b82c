#include <polyloc/eval/scan_alignment.hpp>
#include <polyloc/mcl/refine.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc {

ScanAlignment alignScan(const RayCaster& caster, const Rig& rig, size_t sensor, std::span<const float> ranges,
                        const Pose& guess, const AlignmentSearch& o) {
  const RefineScan scan{sensor, ranges, Pose()};
  const std::span<const RefineScan> scans(&scan, 1);
  const PoseSearchResult s = searchPose(caster, rig, scans, guess, o.search);
  ScanAlignment res;
  res.pose = s.pose;
  res.beams = s.beams;
  res.inliers = s.inliers;
  const RefineResult r = refinePose(caster, rig, scans, s.pose, 3, o.refine);
  res.refine_reason = r.reason;
  res.rms_m = r.rms;
  if (r.accepted) {
    const Eigen::Vector2d h(std::cos(r.pose.yaw()), std::sin(r.pose.yaw())), n(-h.y(), h.x());
    const Eigen::Matrix2d c = r.covariance.topLeftCorner<2, 2>();
    res.std_along = std::sqrt(std::max(0.0, h.dot(c * h)));
    res.std_across = std::sqrt(std::max(0.0, n.dot(c * n)));
    res.pose = r.pose;
    res.refined = true;
    res.rms_m = r.rms;
    res.inliers = r.correspondences;
  }
  return res;
}

double rangeBiasAt(const RayCaster& caster, const Rig& rig, size_t sensor, std::span<const float> ranges,
                   const Pose& map_T_base) {
  const RefineScan scan{sensor, ranges, Pose()};
  RefineConfig rc = AlignmentSearch().refine;
  rc.search_xy = 0.10, rc.search_yaw = 0.0349065850398866;  // the alignment's window, then the fit with the bias
  rc.range_bias = true;
  const RefineResult r = refinePose(caster, rig, std::span<const RefineScan>(&scan, 1), map_T_base, 3, rc);
  return r.accepted ? r.range_bias : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace polyloc
