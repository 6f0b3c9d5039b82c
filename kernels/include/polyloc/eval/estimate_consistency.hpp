// Is a localiser honest? What a controller trusts is the status and the covariance, so they are
// judged against the truth (docs/localization.md "Never confidently wrong"):
//
// - frames published as `tracking` farther than `confident_limit_m` from the truth (must be 0);
// - jumps: consecutive estimates whose errors differ by more than `jump_m` (the estimate moved by
//   that much more or less than the robot did: a relocalisation, or particles taking over;
//   measured against the truth, so that a long step on bad odometry is not one); announced when
//   either frame is not `tracking` (the status changed with it), unannounced otherwise (must be 0);
// - NEES (normalised estimation error squared) of the tracking frames: e' P^-1 e with the planar
//   position error e and the estimate's x-y covariance P; with an honest covariance its mean is 2
//   and 5 % of the frames exceed the chi-square 95 % bound 5.99. Far above: the covariance claims
//   more certainty than the estimate has.
//
//   Consistency c = evaluateConsistency(published, GroundTruth(truth), odometry);
#pragma once

#include <polyloc/eval/ground_truth.hpp>
#include <polyloc/mcl/localizer.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace polyloc {

struct PublishedPose {
  int64_t stamp_ns = 0;
  Pose pose;
  Eigen::Matrix2d cov_xy = Eigen::Matrix2d::Zero();  // m^2
  MclStatus status = MclStatus::Tracking;
};

struct ConsistencyOptions {
  double confident_limit_m = 0.5;
  double jump_m = 0.5;
  double min_std_m = 0.001;  // floor of each position std in the NEES (a collapsed cloud reads 1e-10 m)
};

struct Consistency {
  size_t frames = 0, tracking = 0;      // evaluated (truth known), of them published as tracking
  size_t tracking_beyond = 0;           // tracking frames beyond confident_limit_m
  double worst_tracking_err_m = 0;
  size_t jumps = 0, unannounced_jumps = 0;
  double worst_unannounced_jump_m = 0;
  double nees_mean = 0;                 // position NEES over the tracking frames (NaN without)
  double nees_over_95 = 0;              // share of them above the chi-square 95 % bound (2 dof)
};

// Frames without truth are skipped (a jump is judged between consecutive frames with truth).
Consistency evaluateConsistency(std::span<const PublishedPose> published, const GroundTruth& truth,
                                const ConsistencyOptions& options = {});

}  // namespace polyloc
