// Motion detection on analytic scans: ego-motion and laser shadows give nothing, a moving box
// gives one detection where it is (also walking straight away), bad input is rejected or
// counted without a crash.
#include "tracking_fixtures.hpp"

#include <polyloc/tracking/detections.hpp>
#include <polyloc/tracking/motion_detector.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_motion {

using namespace polyloc;
using test::kTestStep;
using test::Scene2D;


Pose level(double x, double y, double yaw) { return Pose::fromXYZRPY(x, y, 0.1, 0, 0, yaw); }

// Room 10 m x 6 m with two pillars: their shadows open up as the robot drives past.
Scene2D pillaredRoom() {
  return Scene2D::room(5, 3).with({0.0, 0.8}, 0.2).with({1.5, -1.2}, 0.3);
}


TEST(TrackingMotion, StaticSceneWithEgoMotionGivesNothing) {
  const PlanarScannerSpec spec = sickS300();
  const Scene2D scene = pillaredRoom();
  MotionDetector det(spec, MotionConfig{});
  size_t moved = 0;
  for (int k = 0; k < 60; ++k) {  // 4.8 s: drives 4.7 m past both pillars while turning 90 deg
    const double s = k / 59.0;
    const Pose p = level(-3.5 + 4.7 * s, -1.8 + 0.8 * s, 0.5 * M_PI * s);
    std::vector<MotionPoint> out;
    ASSERT_EQ(det.detect(k * kTestStep, p, test::scan2d(spec, p, scene), out), ScanCheck::Ok);
    moved += out.size();
  }
  EXPECT_EQ(moved, 0u);
  EXPECT_EQ(det.counters().scans, 60u);
  EXPECT_EQ(det.counters().pose_jumps, 0u);
}

TEST(TrackingMotion, ShadowsOfAPassingRobotAreNotMotion) {
  // Behind a wide pillar the robot, driving sideways, uncovers metres of wall it never saw.
  const PlanarScannerSpec spec = sickS300();
  const Scene2D scene = Scene2D::room(5, 3).with({0.0, 0.0}, 0.6);
  MotionDetector det(spec, MotionConfig{});
  size_t moved = 0;
  for (int k = 0; k < 40; ++k) {
    const Pose p = level(-2.5, -2.5 + 0.12 * k, 0.0);
    std::vector<MotionPoint> out;
    det.detect(k * kTestStep, p, test::scan2d(spec, p, scene), out);
    moved += out.size();
  }
  EXPECT_EQ(moved, 0u);
}

TEST(TrackingMotion, MovingBoxGivesOneDetectionAtItsPlace) {
  const PlanarScannerSpec spec = sickS300();
  const Scene2D room = Scene2D::room(5, 3).with({1.5, -1.2}, 0.3);  // a pillar, never in the way
  MotionDetector det(spec, MotionConfig{});
  ClusterConfig cc;
  cc.surface_offset = 0.15;  // the box's half size: its centre lies that far behind the faces seen
  size_t steps = 0, found = 0;
  for (int k = 0; k < 50; ++k) {
    const double t = k * 0.08;
    const Eigen::Vector2d box(2.5, -2.0 + 1.0 * t);  // walks north at 1 m/s, 4 m ahead
    const Pose p = level(-1.5 + 0.2 * t, 0.0, 0.0);  // the robot creeps forward
    std::vector<MotionPoint> out;
    det.detect(k * kTestStep, p, test::scan2d(spec, p, room.with(box, 0.15)), out);
    const std::vector<Detection> d = clusterDetections(out, cc, k * kTestStep);
    if (t < 1.3) continue;  // the references fill up
    ++steps;
    ASSERT_LE(d.size(), 1u) << "t = " << t;
    if (d.empty()) continue;
    ++found;
    EXPECT_LT((d[0].position - box).norm(), 0.1) << "t = " << t;
    EXPECT_GE(d[0].points, 3u);
  }
  EXPECT_EQ(found, steps);
}

TEST(TrackingMotion, BoxWalkingStraightAwayIsFound) {
  // It stays in its own shadow: only the receded test sees it.
  const PlanarScannerSpec spec = sickS300();
  const Scene2D room = Scene2D::room(6, 3);
  MotionDetector det(spec, MotionConfig{});
  size_t steps = 0, found = 0;
  for (int k = 0; k < 50; ++k) {
    const double t = k * 0.08;
    const Eigen::Vector2d box(-3.0 + 1.0 * t, 0.0);
    const Pose p = level(-4.5, 0.0, 0.0);
    std::vector<MotionPoint> out;
    det.detect(k * kTestStep, p, test::scan2d(spec, p, room.with(box, 0.15)), out);
    const std::vector<Detection> d = clusterDetections(out, ClusterConfig{}, k * kTestStep);
    if (t < 1.3) continue;
    ++steps;
    for (const Detection& x : d) {
      EXPECT_LT((x.position - box).norm(), 0.25) << "t = " << t;
      ++found;
    }
  }
  EXPECT_GE(found, steps * 3 / 4);
}

TEST(TrackingMotion, BadInputIsRejectedOrCounted) {
  const PlanarScannerSpec spec = sickS300();
  const Scene2D scene = pillaredRoom();
  MotionDetector det(spec, MotionConfig{});
  std::vector<MotionPoint> out;
  const Pose p = level(0, -2, 0.3);
  std::vector<float> r = test::scan2d(spec, p, scene);
  EXPECT_EQ(det.detect(0, p, std::vector<float>(10, 1.f), out), ScanCheck::WrongSize);
  EXPECT_EQ(det.detect(0, p, {}, out), ScanCheck::WrongSize);
  const Pose nan_pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(std::nan(""), 0, 0));
  EXPECT_EQ(det.detect(0, nan_pose, r, out), ScanCheck::BadPose);
  EXPECT_EQ(det.counters().rejected, 3u);
  // NaN, negative and no-echo ranges in a static scene: counted, never motion.
  for (int k = 0; k < 30; ++k) {
    std::vector<float> bad = r;
    for (size_t i = size_t(k % 3); i < bad.size(); i += 3) bad[i] = std::numeric_limits<float>::quiet_NaN();
    bad[7] = -1.f;
    bad[11] = std::numeric_limits<float>::infinity();
    bad[13] = float(spec.range_max);
    ASSERT_EQ(det.detect(k * kTestStep, p, bad, out), ScanCheck::Ok);
  }
  EXPECT_TRUE(out.empty());
  EXPECT_GE(det.counters().invalid_ranges, 30u * (r.size() / 3));
  EXPECT_EQ(det.detect(29 * kTestStep, p, r, out), ScanCheck::OutOfOrder);
  EXPECT_EQ(scanCheckName(ScanCheck::OutOfOrder), std::string("stamp not after the previous scan"));
}

TEST(TrackingMotion, PoseJumpIsNotMotion) {
  const PlanarScannerSpec spec = sickS300();
  const Scene2D scene = pillaredRoom();
  MotionDetector det(spec, MotionConfig{});
  std::vector<MotionPoint> out;
  const Pose truth = level(-2, -1, 0.2);
  for (int k = 0; k < 20; ++k) det.detect(k * kTestStep, truth, test::scan2d(spec, truth, scene), out);
  // Relocalised: the same scan now comes with a pose 1 m and 20 deg off.
  const Pose wrong = level(-1, -1, 0.55);
  for (int k = 20; k < 25; ++k) det.detect(k * kTestStep, wrong, test::scan2d(spec, truth, scene), out);
  EXPECT_TRUE(out.empty());
  EXPECT_GE(det.counters().pose_jumps, 1u);
}

TEST(TrackingMotion, LookSeesEmptyOccupiedAndHidden) {
  const PlanarScannerSpec spec = sickS300();
  MotionDetector det(spec, MotionConfig{});
  std::vector<MotionPoint> out;
  const Pose p = level(-4, 0, 0);
  det.detect(0, p, test::scan2d(spec, p, Scene2D::room(5, 3).with({0, 0}, 0.2)), out);
  EXPECT_EQ(det.look({-2, 0.5}, 0.3), MotionDetector::Look::Empty);
  EXPECT_EQ(det.look({-0.2, 0}, 0.3), MotionDetector::Look::Occupied);
  EXPECT_EQ(det.look({2, 0}, 0.3), MotionDetector::Look::Hidden);   // behind the pillar
  EXPECT_EQ(det.look({-6, 0}, 0.3), MotionDetector::Look::Hidden);  // behind the scanner
}

}  // namespace polyloc::t_tracking_motion
