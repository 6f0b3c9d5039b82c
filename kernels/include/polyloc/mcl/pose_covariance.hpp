// The covariance of the published pose (x, y, yaw, map frame), carried from round to round as an
// EKF carries it: the prediction adds the odometry's noise and moves the last heading error into
// position by the step's lever arm; a refinement's fit is fused in. A collapsed particle cloud
// reads millimetres however well the pose is known; this does not: along a corridor the fit
// leaves the position open, the odometry's noise piles up, and the status can say so. The
// innovation (the fit against the prediction) is also the test of whether both can be right.
//
//   PoseCovariance c;  c.restart(planarCovariance(estimate.covariance));
//   double nis = c.update(last_pose, odom_step, noise, refined_pose, &fit_cov);  // each round
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/config.hpp>

#include <Eigen/Core>

namespace polyloc {

// The x, y, yaw block of a 6x6 covariance (x y z roll pitch yaw), and back into one.
Eigen::Matrix3d planarCovariance(const Eigen::Matrix<double, 6, 6>& cov);
void setPlanarCovariance(Eigen::Matrix<double, 6, 6>& cov, const Eigen::Matrix3d& planar);
// The largest position std (m) of an x, y, yaw covariance.
double maxPositionStd(const Eigen::Matrix3d& cov);

class PoseCovariance {
 public:
  void invalidate() { valid_ = false; }
  void restart(const Eigen::Matrix3d& cov);
  bool valid() const { return valid_; }
  const Eigen::Matrix3d& covariance() const { return cov_; }

  // One round: the covariance carried from `pose` over `delta` (pose frame) with `noise`
  // (propagateCovariance); with a fit (`fit`: its covariance, `now`: the fitted pose), fused
  // with it. Returns the fit's normalised innovation squared against the prediction (3 dof),
  // 0 without a fit; `floor` (std of x, y, yaw) is added to the innovation's covariance only,
  // the errors neither model carries (a fit's covariance from the scan's curvature is
  // millimetres in a well-constrained room). Not valid before restart().
  double update(const Pose& pose, const Pose& delta, const MotionNoise& noise, const Pose& now,
                const Eigen::Matrix3d* fit, const Eigen::Vector3d& floor = Eigen::Vector3d::Zero());

 private:
  Eigen::Matrix3d cov_ = Eigen::Matrix3d::Zero();
  bool valid_ = false;
};

}  // namespace polyloc
