// How good is this robot's odometry? The motion model's noise (mcl.motion alphas) is a guess made
// before the robot drove; real odometry is better or much worse (a worn wheel, a carpet, a log
// whose odometry was made elsewhere). When the filter's noise is smaller than the odometry's
// error, the cloud cannot follow and the track is lost at the first sharp turn (real logs with
// 10 %/2 deg per m drift: a 55 deg heading error in one step); when it is much larger, the cloud
// spreads for nothing. So the noise is scaled by what the scans say about the odometry:
//
// Each pair of consecutive rounds whose estimates were refined against the map (the scan-matched
// motion) gives an innovation: the refined pose now against the previous refined pose moved by
// the odometry between them. Its covariance S is the motion model's for that step (the alphas
// times the current scales) plus both refinements' covariances. The normalised innovation
// squared, separately for position (2 dof) and heading (1 dof), should average its dof; the
// scales follow the log of that ratio by exponential smoothing (`gain` per pair), each clamped to
// [min_scale, max_scale], so one slip moves them a little and a run of bad steps a lot
// (adaptive process noise from the innovation sequence, as Mehra's and Sage-Husa's filters do).
//
//   OdometryNoise n(config.motion.adapt);
//   n.addPair(prev_refined, prev_cov, now_refined, now_cov, odom_delta, config.motion);
//   MotionNoise used = n.scaled(config.motion);
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/config.hpp>

#include <Eigen/Core>

namespace polyloc {

// Covariance (x, y, yaw in the start frame) of the motion model's noise for one planar step.
Eigen::Matrix3d motionCovariance(const Pose& delta, const MotionNoise& noise);

// A planar pose's covariance (x, y, yaw, map frame) carried over one step `delta` (in the pose's
// frame) with the motion noise: the heading's error moves the position by the step's lever arm.
Eigen::Matrix3d propagateCovariance(const Eigen::Matrix3d& cov, const Pose& pose, const Pose& delta,
                                    const MotionNoise& noise);

class OdometryNoise {
 public:
  explicit OdometryNoise(const OdometryNoiseAdapt& config = {}) : config_(config) {}

  // One innovation. cov_*: 6x6 (x y z roll pitch yaw) in the map frame. Returns false (and
  // changes nothing) when the step is too short to say anything or a covariance is not usable.
  bool addPair(const Pose& prev, const Eigen::Matrix<double, 6, 6>& prev_cov, const Pose& now,
               const Eigen::Matrix<double, 6, 6>& now_cov, const Pose& odom_delta, const MotionNoise& base);

  // The alphas multiplied by the current scales (translation: alpha3, alpha4; rotation: alpha1,
  // alpha2); the rest as given.
  MotionNoise scaled(const MotionNoise& base) const;
  double translationScale() const { return trans_; }
  double rotationScale() const { return rot_; }
  size_t pairs() const { return pairs_; }
  // Normalised innovation squared of the last pair (position, heading).
  double lastNisPosition() const { return last_nis_xy_; }
  double lastNisHeading() const { return last_nis_yaw_; }
  void reset() { trans_ = rot_ = 1.0, pairs_ = 0; }

 private:
  OdometryNoiseAdapt config_;
  double trans_ = 1.0, rot_ = 1.0;
  double last_nis_xy_ = 0, last_nis_yaw_ = 0;
  size_t pairs_ = 0;
};

}  // namespace polyloc
