#include <polyloc/eval/scan_alignment.hpp>
#include <polyloc/mcl/refine.hpp>

#include <cmath>

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

}  // namespace polyloc
