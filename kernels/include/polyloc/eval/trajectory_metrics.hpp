// Accuracy of an estimated trajectory against ground truth, both in the map frame (no
// alignment). Each estimate is compared with the ground truth interpolated at its stamp;
// estimates outside the ground truth's span (or in one of its gaps) are skipped and counted.
//
//   TrajectoryMetrics m = evaluateTrajectory(estimates, GroundTruth(readTum("gt.tum")));
//   m.all.ate_rmse_m, m.converged_after_s, m.after_convergence.p95_pos_err_m, m.frames[i]...
//
// Convergence (docs/localization.md, "Metrics"): the first frame with status tracking from which every frame of the
// next `hold_s` seconds has a planar position error < `pos_m` and |yaw error| < `yaw_deg`,
// and the run lasts at least `hold_s` beyond it. Later divergence does not undo it: frames
// after the convergence time all count in `after_convergence`, so a lost track shows there.
#pragma once

#include <polyloc/eval/ground_truth.hpp>
#include <polyloc/mcl/localizer.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace polyloc {

struct EstimatedPose {
  int64_t stamp_ns = 0;
  Pose pose;  // map_T_base
  MclStatus status = MclStatus::Tracking;
};

struct FrameError {
  int64_t stamp_ns = 0;
  double t_s = 0;           // since MetricsOptions::start_ns
  Pose estimate, truth;
  double dx = 0, dy = 0, dz = 0;  // estimate - truth, map frame (m)
  double pos_err = 0;             // planar: hypot(dx, dy)
  double yaw_err = 0, roll_err = 0, pitch_err = 0;  // signed, wrapped to (-pi, pi] (rad)
  MclStatus status = MclStatus::Tracking;
  bool converged = false;   // at or after the convergence time
};

// NaN where there are no frames (JSON: null).
struct ErrorSummary {
  size_t frames = 0;
  double ate_rmse_m = 0, mean_pos_err_m = 0, p95_pos_err_m = 0, max_pos_err_m = 0;  // planar x, y
  double yaw_rmse_deg = 0, p95_yaw_err_deg = 0, max_yaw_err_deg = 0;
  double z_rmse_m = 0, max_z_err_m = 0;
  double roll_pitch_rmse_deg = 0;  // roll and pitch errors pooled: sqrt(mean(droll^2 + dpitch^2) / 2)
  double max_roll_pitch_err_deg = 0;
};

struct MetricsOptions {
  double converge_pos_m = 0.2;
  double converge_yaw_deg = 5.0;
  double converge_hold_s = 1.0;
  // Origin of t_s and converged_after_s (e.g. when the filter was initialised); 0 = the stamp of
  // the first estimate given.
  int64_t start_ns = 0;
};

struct TrajectoryMetrics {
  size_t estimates = 0;         // given
  size_t skipped = 0;           // outside the ground truth's span or in a gap, or not finite
  ErrorSummary all;             // every evaluated frame
  std::optional<double> converged_after_s;  // nullopt: never converged
  int64_t converged_at_ns = 0;
  ErrorSummary after_convergence;  // frames at or after convergence (frames = 0 if never)
  std::array<size_t, 4> frames_by_status{};  // indexed by MclStatus
  std::vector<FrameError> frames;  // per evaluated frame, in stamp order
};

// Estimates need not be sorted (they are, stably, by stamp).
TrajectoryMetrics evaluateTrajectory(std::vector<EstimatedPose> estimates, const GroundTruth& truth,
                                     const MetricsOptions& options = {});
// The summary of any subset of frames (e.g. a time window for a plot).
ErrorSummary summarize(std::span<const FrameError> frames);

// RMSE of the planar position error along the true heading and across it (0 without frames):
// a corridor leaves the position open along it, so there the error is mostly along.
struct HeadingSplit {
  double along_rmse_m = 0, across_rmse_m = 0;
};
HeadingSplit splitByHeading(std::span<const FrameError> frames);

}  // namespace polyloc
