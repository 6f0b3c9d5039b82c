// Trajectory metrics on synthetic trajectories with known errors: a constant offset gives that
// offset as RMSE, percentiles as numpy computes them, interpolated ground truth, yaw errors
// across +-pi, the convergence rule, and bad input (gaps, NaN, outside the span) skipped.
#include <polyloc/eval/stats.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace polyloc::t_eval_metrics {  // the file's own: the suite is compiled in batches (unity build)
namespace {

constexpr int64_t kSec = 1000000000;
constexpr int64_t kT0 = 1700000000 * kSec;

// A circle of radius 2 m at 0.5 rad/s, yaw along the path, sampled every `dt_ms`.
std::vector<StampedPose> circle(double seconds, int dt_ms, double z = 0, double pitch = 0) {
  std::vector<StampedPose> out;
  for (int64_t ms = 0; ms <= static_cast<int64_t>(seconds * 1000); ms += dt_ms) {
    const double t = ms * 1e-3, a = 0.5 * t;
    out.push_back({kT0 + ms * 1000000,
                   Pose::fromXYZRPY(2 * std::cos(a), 2 * std::sin(a), z, 0, pitch, wrapAngle(a + M_PI / 2))});
  }
  return out;
}

std::vector<EstimatedPose> estimatesFrom(const std::vector<StampedPose>& truth, const Pose& offset_in_base) {
  std::vector<EstimatedPose> out;
  for (const auto& p : truth) out.push_back({p.stamp_ns, p.pose * offset_in_base, MclStatus::Tracking});
  return out;
}

TEST(EvalStats, PercentileInterpolatesLikeNumpy) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // unsorted on purpose
  EXPECT_DOUBLE_EQ(percentile(v, 95), 95.05);     // numpy.percentile(range(1, 101), 95)
  EXPECT_DOUBLE_EQ(percentile(v, 50), 50.5);
  EXPECT_DOUBLE_EQ(percentile(v, 0), 1);
  EXPECT_DOUBLE_EQ(percentile(v, 100), 100);
  EXPECT_DOUBLE_EQ(percentile({3.0}, 95), 3.0);
  EXPECT_DOUBLE_EQ(percentile({1.0, 2.0}, 95), 1.95);
  EXPECT_TRUE(std::isnan(percentile({}, 95)));
}

TEST(EvalStats, RmsAndMax) {
  const std::vector<double> v{3, -4};
  EXPECT_DOUBLE_EQ(rms(v), std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(maxAbs(v), 4);
  EXPECT_TRUE(std::isnan(rms(std::vector<double>{})));
}

TEST(EvalGroundTruth, InterpolatesBetweenNeighbours) {
  GroundTruth gt({{kT0 + kSec, Pose::fromXYZRPY(2, 0, 0.2, 0, 0, 0.4)},
                  {kT0, Pose::fromXYZRPY(0, 0, 0, 0, 0, 0)}});  // unsorted on purpose
  const auto mid = gt.at(kT0 + kSec / 4);
  ASSERT_TRUE(mid);
  EXPECT_NEAR(mid->x(), 0.5, 1e-12);
  EXPECT_NEAR(mid->z(), 0.05, 1e-12);
  EXPECT_NEAR(mid->yaw(), 0.1, 1e-12);
  EXPECT_TRUE(gt.at(kT0)->isApprox(Pose()));
  EXPECT_NEAR(gt.at(kT0 + kSec)->x(), 2, 1e-12);
  EXPECT_FALSE(gt.at(kT0 - 1));
  EXPECT_FALSE(gt.at(kT0 + kSec + 1));
}

TEST(EvalGroundTruth, InterpolatesYawAcrossPi) {
  GroundTruth gt({{kT0, Pose::planar(0, 0, M_PI - 0.1)}, {kT0 + kSec, Pose::planar(0, 0, -M_PI + 0.1)}});
  const auto mid = gt.at(kT0 + kSec / 2);
  ASSERT_TRUE(mid);
  EXPECT_NEAR(std::abs(mid->yaw()), M_PI, 1e-9);  // the short way, through pi, not through 0
}

TEST(EvalGroundTruth, DropsBadPosesAndDoesNotBridgeGaps) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  GroundTruth gt({{kT0, Pose::planar(0, 0, 0)},
                  {kT0, Pose::planar(9, 9, 0)},  // repeated stamp: the first wins
                  {kT0 + kSec / 2, Pose::planar(nan, 0, 0)},
                  {kT0 + kSec, Pose::planar(1, 0, 0)},
                  {kT0 + 5 * kSec, Pose::planar(5, 0, 0)}},
                 /*max_gap_s=*/1.0);
  EXPECT_EQ(gt.size(), 3u);
  EXPECT_EQ(gt.dropped(), 2u);
  EXPECT_NEAR(gt.at(kT0 + kSec / 2)->x(), 0.5, 1e-12);
  EXPECT_FALSE(gt.at(kT0 + 3 * kSec));  // 4 s without ground truth
  EXPECT_TRUE(gt.at(kT0 + 5 * kSec));
}

TEST(EvalMetrics, ConstantOffsetGivesThatOffset) {
  const auto truth = circle(20, 20, 0.1, deg2rad(2));
  // 5 cm ahead and 3 cm to the left in the robot's frame, 2 deg of yaw, 4 mm up, 0.5 deg roll.
  const Pose off = Pose::fromXYZRPY(0.05, 0.03, 0.004, deg2rad(0.5), 0, deg2rad(2));
  const TrajectoryMetrics m = evaluateTrajectory(estimatesFrom(truth, off), GroundTruth(truth));
  const double d = std::hypot(0.05, 0.03);
  EXPECT_EQ(m.all.frames, truth.size());
  EXPECT_EQ(m.skipped, 0u);
  EXPECT_NEAR(m.all.ate_rmse_m, d, 2e-4);  // the truth is pitched 2 deg: offsets tilt a little
  EXPECT_NEAR(m.all.p95_pos_err_m, d, 2e-4);
  EXPECT_NEAR(m.all.max_pos_err_m, d, 2e-4);
  EXPECT_NEAR(m.all.yaw_rmse_deg, 2, 0.1);  // Euler coupling with the 2 deg pitch
  EXPECT_NEAR(m.all.p95_yaw_err_deg, 2, 0.1);
  EXPECT_NEAR(m.all.z_rmse_m, 0.004, 3e-3);
  EXPECT_GT(m.all.roll_pitch_rmse_deg, 0.3);
  EXPECT_LT(m.all.roll_pitch_rmse_deg, 0.5);
  ASSERT_TRUE(m.converged_after_s);
  EXPECT_DOUBLE_EQ(*m.converged_after_s, 0);
  EXPECT_EQ(m.after_convergence.frames, m.all.frames);
  EXPECT_EQ(m.frames_by_status[static_cast<size_t>(MclStatus::Tracking)], truth.size());
}

TEST(EvalMetrics, PlanarOffsetExact) {
  const auto truth = circle(10, 50);
  std::vector<EstimatedPose> est;
  for (const auto& p : truth) {
    const Eigen::Vector3d t = p.pose.translation() + Eigen::Vector3d(0.03, -0.04, 0.01);
    est.push_back({p.stamp_ns, Pose(p.pose.rotation(), t)});
  }
  const TrajectoryMetrics m = evaluateTrajectory(est, GroundTruth(truth));
  EXPECT_NEAR(m.all.ate_rmse_m, 0.05, 1e-12);
  EXPECT_NEAR(m.all.z_rmse_m, 0.01, 1e-12);
  EXPECT_NEAR(m.all.yaw_rmse_deg, 0, 1e-9);
  EXPECT_NEAR(m.all.roll_pitch_rmse_deg, 0, 1e-9);
  ASSERT_EQ(m.frames.size(), truth.size());
  EXPECT_NEAR(m.frames[3].dx, 0.03, 1e-12);
  EXPECT_NEAR(m.frames[3].dy, -0.04, 1e-12);
}

TEST(EvalMetrics, YawErrorWrapsAroundPi) {
  // Truth at +179 deg, estimate at -179 deg: 2 deg apart, not 358.
  const std::vector<StampedPose> truth{{kT0, Pose::planar(0, 0, deg2rad(179))},
                                       {kT0 + 2 * kSec, Pose::planar(0, 0, deg2rad(179))}};
  std::vector<EstimatedPose> est;
  for (int i = 0; i <= 20; ++i) est.push_back({kT0 + i * kSec / 10, Pose::planar(0, 0, deg2rad(-179))});
  const TrajectoryMetrics m = evaluateTrajectory(est, GroundTruth(truth));
  EXPECT_NEAR(m.all.yaw_rmse_deg, 2, 1e-9);
  EXPECT_NEAR(m.all.max_yaw_err_deg, 2, 1e-9);
  EXPECT_NEAR(m.frames[0].yaw_err, deg2rad(2), 1e-12);  // -179 - 179 = +2 (mod 360)
}

TEST(EvalMetrics, EstimatesBetweenTruthSamplesUseInterpolation) {
  // Truth at 1 Hz along x at 1 m/s; estimates at 10 Hz exactly on the line: zero error.
  std::vector<StampedPose> truth;
  for (int i = 0; i <= 5; ++i) truth.push_back({kT0 + i * kSec, Pose::planar(i, 0, 0)});
  std::vector<EstimatedPose> est;
  for (int i = -5; i <= 55; ++i) est.push_back({kT0 + i * kSec / 10, Pose::planar(0.1 * i, 0, 0)});
  const TrajectoryMetrics m = evaluateTrajectory(est, GroundTruth(truth));
  EXPECT_EQ(m.skipped, 10u);  // 5 before, 5 after the truth's span
  EXPECT_EQ(m.all.frames, 51u);
  EXPECT_NEAR(m.all.max_pos_err_m, 0, 1e-12);
}

TEST(EvalMetrics, PercentileOfKnownErrorDistribution) {
  // Errors 0.01, 0.02, ..., 1.00 m (shuffled in time): p95 = 0.9505, max = 1, RMSE known.
  std::vector<StampedPose> truth;
  std::vector<EstimatedPose> est;
  double sq = 0;
  for (int i = 0; i < 100; ++i) {
    const double e = 0.01 * ((i * 37) % 100 + 1);
    sq += e * e;
    truth.push_back({kT0 + i * kSec / 10, Pose::planar(i, 0, 0)});
    est.push_back({kT0 + i * kSec / 10, Pose::planar(i, e, 0)});
  }
  const TrajectoryMetrics m = evaluateTrajectory(est, GroundTruth(truth));
  EXPECT_NEAR(m.all.p95_pos_err_m, 0.9505, 1e-12);
  EXPECT_NEAR(m.all.max_pos_err_m, 1.0, 1e-12);
  EXPECT_NEAR(m.all.ate_rmse_m, std::sqrt(sq / 100), 1e-12);
}

TEST(EvalMetrics, ConvergenceNeedsOneSecondWithinBounds) {
  // 10 s at 10 Hz: error 1 m until 2 s, good for 0.5 s, bad again from 2.5 s, good from
  // 3.0 s on except a 0.3 m glitch at 7 s: converged at 3.0 s; the glitch counts afterwards.
  std::vector<StampedPose> truth;
  std::vector<EstimatedPose> est;
  for (int i = 0; i <= 100; ++i) {
    const int64_t t = kT0 + i * kSec / 10;
    double e = i < 20 || (i >= 25 && i < 30) ? 1.0 : 0.01;
    if (i == 70) e = 0.3;
    truth.push_back({t, Pose::planar(0, 0, 0)});
    est.push_back({t, Pose::planar(e, 0, 0), i < 20 ? MclStatus::Initialising : MclStatus::Tracking});
  }
  MetricsOptions o;
  o.start_ns = kT0 - kSec;  // initialised a second before the first estimate
  const TrajectoryMetrics m = evaluateTrajectory(est, GroundTruth(truth), o);
  ASSERT_TRUE(m.converged_after_s);
  EXPECT_NEAR(*m.converged_after_s, 4.0, 1e-9);
  EXPECT_EQ(m.converged_at_ns, kT0 + 3 * kSec);
  EXPECT_EQ(m.after_convergence.frames, 71u);
  EXPECT_NEAR(m.after_convergence.max_pos_err_m, 0.3, 1e-12);
  EXPECT_NEAR(m.all.max_pos_err_m, 1.0, 1e-12);
  EXPECT_FALSE(m.frames[29].converged);
  EXPECT_TRUE(m.frames[30].converged);
  EXPECT_EQ(m.frames_by_status[static_cast<size_t>(MclStatus::Initialising)], 20u);
  // A yaw error of 6 deg also keeps it from converging.
  for (auto& e : est) e.pose = Pose::planar(0, 0, deg2rad(6));
  const TrajectoryMetrics never = evaluateTrajectory(est, GroundTruth(truth), o);
  EXPECT_FALSE(never.converged_after_s);
  EXPECT_EQ(never.after_convergence.frames, 0u);
  EXPECT_TRUE(std::isnan(never.after_convergence.ate_rmse_m));
  // Exact poses from a filter that never said it tracks: not converged either.
  for (size_t i = 0; i < est.size(); ++i) est[i] = {est[i].stamp_ns, truth[i].pose, MclStatus::Uncertain};
  EXPECT_FALSE(evaluateTrajectory(est, GroundTruth(truth), o).converged_after_s);
}

TEST(EvalMetrics, TooShortToShowConvergence) {
  const auto truth = circle(0.5, 20);  // 0.5 s < the 1 s hold
  const TrajectoryMetrics m = evaluateTrajectory(estimatesFrom(truth, Pose()), GroundTruth(truth));
  EXPECT_FALSE(m.converged_after_s);
  EXPECT_NEAR(m.all.ate_rmse_m, 0, 1e-12);
}

TEST(EvalMetrics, BadInputIsSkippedNotFatal) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto truth = circle(5, 100);
  auto est = estimatesFrom(truth, Pose());
  est[3].pose = Pose::planar(nan, 0, 0);
  std::swap(est[5], est[9]);  // out of order: sorted
  const TrajectoryMetrics m = evaluateTrajectory(est, GroundTruth(truth));
  EXPECT_EQ(m.skipped, 1u);
  EXPECT_EQ(m.all.frames, truth.size() - 1);
  EXPECT_NEAR(m.all.ate_rmse_m, 0, 1e-12);
  for (size_t i = 1; i < m.frames.size(); ++i) EXPECT_LT(m.frames[i - 1].stamp_ns, m.frames[i].stamp_ns);
  // No ground truth at all, no estimates at all: empty metrics, NaN summaries.
  const TrajectoryMetrics none = evaluateTrajectory(est, GroundTruth());
  EXPECT_EQ(none.skipped, est.size());
  EXPECT_TRUE(std::isnan(none.all.ate_rmse_m));
  const TrajectoryMetrics empty = evaluateTrajectory({}, GroundTruth(truth));
  EXPECT_EQ(empty.all.frames, 0u);
  EXPECT_FALSE(empty.converged_after_s);
}

// An offset of 3 cm ahead and 4 cm to the left in the robot's frame, on a circle (the heading
// turns all the time): 3 cm along, 4 cm across, whatever the map direction.
TEST(EvalTrajectory, ErrorSplitAlongAndAcrossTheHeading) {
  const auto truth = circle(10, 100);
  const TrajectoryMetrics m = evaluateTrajectory(estimatesFrom(truth, Pose::planar(0.03, 0.04, 0)), GroundTruth(truth));
  const HeadingSplit h = splitByHeading(m.frames);
  EXPECT_NEAR(h.along_rmse_m, 0.03, 1e-6);
  EXPECT_NEAR(h.across_rmse_m, 0.04, 1e-6);
  EXPECT_NEAR(std::hypot(h.along_rmse_m, h.across_rmse_m), m.all.ate_rmse_m, 1e-6);
  EXPECT_EQ(splitByHeading({}).along_rmse_m, 0.0);
}

}  // namespace
}  // namespace polyloc
