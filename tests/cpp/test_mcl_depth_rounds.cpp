// The depth-camera model (pixel grid, flying pixels skipped) and the rounds of a multi-sensor
// rig: a sensor that never delivers does not hold rounds open; estimates carry the stamp of the
// frame their particles were moved to.
#include "mcl_fixtures.hpp"

#include <polyloc/eval/localization_trials.hpp>
#include <polyloc/mcl/depth_model.hpp>

#include <gtest/gtest.h>

namespace polyloc::test::t_mcl_depth_rounds {  // the file's own: the suite is compiled in batches (unity build)
namespace {

Rig scannerAndCamera() {
  Rig rig = scannerRig();
  DepthCameraSpec cam = pmdO3D100();
  rig.add(Sensor{"tof", cam, Pose::fromXYZRPY(0.2, 0, 0.6, 0, deg2rad(10), 0)}, "");
  return rig;
}

}  // namespace

TEST(MclDepthModel, GridSkipsInvalidAndFlyingPixels) {
  DepthCameraSpec cam = pmdO3D100();
  std::vector<float> r(cam.numBeams(), 3.0f);
  DepthModel cfg;
  cfg.pixels = 80;
  const auto all = DepthSensorModel::selectPixels(cam, r, cfg);
  EXPECT_GE(all.size(), 60u);
  EXPECT_LE(all.size(), 140u);
  // A step edge: the right half of the image 2 m further away. Pixels next to the step (within
  // one stride) are skipped, the others stay.
  for (int v = 0; v < cam.height; ++v)
    for (int u = cam.width / 2; u < cam.width; ++u) r[size_t(v * cam.width + u)] = 5.0f;
  const auto edge = DepthSensorModel::selectPixels(cam, r, cfg);
  EXPECT_LT(edge.size(), all.size());
  EXPECT_GT(edge.size(), all.size() / 2);
  // NaN pixels are never chosen.
  std::fill(r.begin(), r.end(), std::numeric_limits<float>::quiet_NaN());
  EXPECT_TRUE(DepthSensorModel::selectPixels(cam, r, cfg).empty());
  // A wrong-sized frame gives nothing rather than reading past its end.
  EXPECT_TRUE(DepthSensorModel::selectPixels(cam, std::vector<float>(10, 3.f), cfg).empty());
}

TEST(MclDepthModel, TracksWithScannerAndCamera) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerAndCamera();
  MclConfig cfg;
  cfg.particles = 1000;
  ASSERT_EQ(cfg.depth_model, "depth");
  Localizer loc(caster, mesh, rig, cfg);
  const auto truth = loopTrajectory(40);
  loc.initPose(Pose::planar(truth[0].x() + 0.1, truth[0].y() - 0.1, truth[0].yaw() + 0.05), planarCov(0.15, 0.08), 0);
  size_t rounds = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    loc.addOdometry(t, truth[i]);
    loc.addScan(0, t, simulateScan(caster, rig.sensors[0], truth[i], 0.01, 2 * i));
    rounds += loc.addScan(1, t + 1'000'000, simulateScan(caster, rig.sensors[1], truth[i], 0.01, 2 * i + 1));
  }
  const MclEstimate e = loc.estimate();
  EXPECT_GE(rounds, 30u);  // a round ends with the camera's frame, its sensor due last
  EXPECT_EQ(e.stamp_ns, int64_t(truth.size() - 1) * 100'000'000 + 1'000'000);
  EXPECT_LT(posErr(e.pose, truth.back()), 0.05);
  EXPECT_LT(yawErrDeg(e.pose, truth.back()), 2.0);
}

TEST(MclRounds, SilentSensorDoesNotHoldRoundsOpen) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerAndCamera();  // the camera never sends a frame
  MclConfig cfg;
  cfg.particles = 500;
  Localizer loc(caster, mesh, rig, cfg);
  const auto truth = loopTrajectory(30);
  loc.initPose(truth[0], planarCov(0.05, 0.03), 0);
  size_t rounds = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    loc.addOdometry(t, truth[i]);
    rounds += loc.addScan(0, t, simulateScan(caster, rig.sensors[0], truth[i], 0.01, i));
  }
  EXPECT_EQ(rounds, truth.size());  // every scan ends its round: nothing waits for the camera
  EXPECT_EQ(loc.estimate().stamp_ns, int64_t(truth.size() - 1) * 100'000'000);
  EXPECT_LT(posErr(loc.estimate().pose, truth.back()), 0.05);
}

TEST(MclRounds, CameraThatStopsIsNoLongerWaitedFor) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerAndCamera();
  MclConfig cfg;
  cfg.particles = 500;
  Localizer loc(caster, mesh, rig, cfg);
  const auto truth = loopTrajectory(40);
  loc.initPose(truth[0], planarCov(0.05, 0.03), 0);
  size_t late_rounds = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    loc.addOdometry(t, truth[i]);
    const bool closed = loc.addScan(0, t, simulateScan(caster, rig.sensors[0], truth[i], 0.01, i));
    if (i < 10) loc.addScan(1, t + 1'000'000, simulateScan(caster, rig.sensors[1], truth[i], 0.01, 100 + i));
    if (i >= 25) late_rounds += closed;  // more than a second after the camera's last frame
  }
  EXPECT_EQ(late_rounds, truth.size() - 25);
  EXPECT_LT(posErr(loc.estimate().pose, truth.back()), 0.05);
}

TEST(LocalizationTrials, ConvergedRoundNeedsTheErrorToStayWithinTolerance) {
  EXPECT_EQ(convergedRound({1.0, 0.1, 0.05, 0.02}, {0.0, 0.0, 0.0, 0.0}, 0.2, 0.1), 2);
  EXPECT_EQ(convergedRound({0.1, 0.5, 0.05, 0.02}, {0.0, 0.0, 0.0, 0.0}, 0.2, 0.1), 3);
  EXPECT_EQ(convergedRound({0.1, 0.1, 0.1}, {0.0, 0.0, 0.2}, 0.2, 0.1), -1);  // yaw off at the end
  EXPECT_EQ(convergedRound({}, {}, 0.2, 0.1), -1);
}

}  // namespace polyloc::test
