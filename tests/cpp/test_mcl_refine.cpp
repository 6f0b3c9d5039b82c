// Point-to-plane refinement of an MCL estimate (mcl/refine.hpp) in the rooms of mcl_fixtures.hpp.
#include "mcl_fixtures.hpp"

#include <polyloc/mcl/refine.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace polyloc::test::t_mcl_refine {  // the file's own: the suite is compiled in batches (unity build)
namespace {

double angleErrDeg(double a, double b) { return std::abs(rad2deg(angleDiff(a, b))); }

// One scan per rig sensor, simulated from the true pose, taken at the reference time.
struct Scans {
  std::vector<std::vector<float>> ranges;
  std::vector<RefineScan> scans;
  Scans(const RayCaster& caster, const Rig& rig, const Pose& truth, double sigma) {
    for (size_t s = 0; s < rig.size(); ++s) ranges.push_back(simulateScan(caster, rig.sensors[s], truth, sigma, s));
    for (size_t s = 0; s < rig.size(); ++s) scans.push_back(RefineScan{s, ranges[s], Pose()});
  }
};

// The scanner rig plus a scanner 1 m up, pitched 35 deg down: floor and ceiling hits make z,
// roll and pitch observable.
Rig tiltedRig() {
  Rig rig = scannerRig();
  PlanarScannerSpec spec = std::get<PlanarScannerSpec>(rig.sensors[0].spec);
  rig.add(Sensor{"tilted", spec, Pose::fromXYZRPY(0.2, 0.0, 1.0, 0, deg2rad(35.0), 0)}, "");
  return rig;
}

const Pose kTruth = Pose::planar(-0.6, 0.4, 0.5);

TEST(MclRefine, NoiseFreeConvergesFromFiveCmTwoDeg) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const Scans s(caster, rig, kTruth, 0.0);
  const Pose start = Pose::planar(kTruth.x() + 0.03, kTruth.y() - 0.04, kTruth.yaw() + deg2rad(2.0));
  const RefineResult r = refinePose(caster, rig, s.scans, start, 3, RefineConfig{});
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT(posErr(r.pose, kTruth), 0.002);
  EXPECT_LT(yawErrDeg(r.pose, kTruth), 0.05);
  EXPECT_NEAR(r.pose.z(), 0.0, 1e-9);  // held in 3 DoF
  EXPECT_GE(r.correspondences, 150u);
  EXPECT_LT(r.rms, 0.002);
  EXPECT_LE(r.iterations, 10);
}

TEST(MclRefine, NoisyScanWithinOneCm) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const Scans s(caster, rig, kTruth, 0.01);
  const Pose start = Pose::planar(kTruth.x() - 0.04, kTruth.y() + 0.03, kTruth.yaw() - deg2rad(2.0));
  const RefineResult r = refinePose(caster, rig, s.scans, start, 3, RefineConfig{});
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT(posErr(r.pose, kTruth), 0.01);
  EXPECT_LT(yawErrDeg(r.pose, kTruth), 0.3);
  EXPECT_GT(r.rms, 0.005);  // the noise shows in the residuals
  EXPECT_LT(r.rms, 0.02);
  // The covariance is a sane, small, positive one in x, y, yaw; nothing in the held axes.
  EXPECT_GT(r.covariance(0, 0), 0.0);
  EXPECT_LT(std::sqrt(r.covariance(0, 0)), 0.01);
  EXPECT_LT(std::sqrt(r.covariance(5, 5)), deg2rad(0.5));
  EXPECT_EQ(r.covariance(2, 2), 0.0);
}

TEST(MclRefine, SixDofWithTiltedScanner) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = tiltedRig();
  const Pose truth = Pose::fromXYZRPY(-0.6, 0.4, 0.0, 0, 0, 0.5);
  const Scans s(caster, rig, truth, 0.005);
  const Pose start = Pose::fromXYZRPY(-0.58, 0.39, 0.03, deg2rad(1.0), deg2rad(-1.0), 0.5 + deg2rad(1.0));
  const RefineResult r = refinePose(caster, rig, s.scans, start, 6, RefineConfig{});
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 0.005);
  EXPECT_LT(angleErrDeg(r.pose.roll(), truth.roll()), 0.2);
  EXPECT_LT(angleErrDeg(r.pose.pitch(), truth.pitch()), 0.2);
  EXPECT_LT(angleErrDeg(r.pose.yaw(), truth.yaw()), 0.2);
  for (int i = 0; i < 6; ++i) EXPECT_GT(r.covariance(i, i), 0.0) << i;
}

TEST(MclRefine, ScansAtOtherStampsUseOdometry) {
  // The scan was taken 0.2 m further on; base_T_base_at_scan carries it back to the reference.
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const Pose odo = Pose::planar(0.2, 0.0, 0.05);
  const auto ranges = simulateScan(caster, rig.sensors[0], kTruth * odo, 0.0, 0);
  const RefineScan scan{0, ranges, odo};
  const Pose start = Pose::planar(kTruth.x() + 0.03, kTruth.y() + 0.03, kTruth.yaw() + deg2rad(1.5));
  const RefineResult r = refinePose(caster, rig, std::span(&scan, 1), start, 3, RefineConfig{});
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT(posErr(r.pose, kTruth), 0.002);
  EXPECT_LT(yawErrDeg(r.pose, kTruth), 0.05);
}

TEST(MclRefine, CorridorIsUncertainAlongItsAxis) {
  // Two parallel walls along x, 2 m apart, far longer than the scanner's range: x is unobserved.
  Mesh m;
  mapgen::MeshBuilder b(m);
  b.box({-60.f, -1.2f, 0.f}, {60.f, -1.f, 2.5f}, "wall");
  b.box({-60.f, 1.f, 0.f}, {60.f, 1.2f, 2.5f}, "wall");
  const EmbreeCaster caster(m);
  const Rig rig = scannerRig();
  const Pose truth = Pose::planar(0.0, 0.2, 0.1);
  const Scans s(caster, rig, truth, 0.005);
  const Pose start = Pose::planar(0.0, 0.23, 0.1 + deg2rad(1.0));
  const RefineResult r = refinePose(caster, rig, s.scans, start, 3, RefineConfig{});
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_NEAR(r.pose.y(), truth.y(), 0.005);
  EXPECT_NEAR(r.pose.x(), start.x(), 1e-3);  // no step along the unobserved axis
  EXPECT_TRUE(r.covariance.allFinite());
  EXPECT_GT(r.covariance(0, 0), 1e4 * r.covariance(1, 1));
}

TEST(MclRefine, AllInvalidBeamsAreRefused) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const std::vector<float> nan(rig.sensors[0].beams().size(), std::numeric_limits<float>::quiet_NaN());
  const RefineScan scan{0, nan, Pose()};
  const Pose start = Pose::planar(0.1, 0.2, 0.3);
  const RefineResult r = refinePose(caster, rig, std::span(&scan, 1), start, 3, RefineConfig{});
  EXPECT_FALSE(r.accepted);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_TRUE(r.pose.isApprox(start));
}

TEST(MclRefine, UnmappedObstacleDoesNotPull) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  Scans s(caster, rig, kTruth, 0.0);
  for (size_t b = 60; b < 110; ++b) s.ranges[0][b] -= 0.5f;  // someone standing in 50 deg of the scan
  const Pose start = Pose::planar(kTruth.x() + 0.03, kTruth.y() - 0.04, kTruth.yaw() + deg2rad(2.0));
  const RefineResult r = refinePose(caster, rig, s.scans, start, 3, RefineConfig{});
  ASSERT_TRUE(r.accepted) << r.reason;
  EXPECT_LT(posErr(r.pose, kTruth), 0.003);
  EXPECT_LT(yawErrDeg(r.pose, kTruth), 0.1);
}

// With the correspondence gate at 0.15 m, Gauss-Newton from 1 m off does not travel 1 m: it
// settles where some walls agree, and an inlier ratio of 0.7 (not max_correction) refuses it.
// The default 0.5 lets some of these through: real scans need it, and the fit check
// (test_mcl_fit.cpp) is what refuses a wrong place then.
TEST(MclRefine, StartFarOffIsRefused) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const Scans s(caster, rig, kTruth, 0.01);
  RefineConfig cfg;
  cfg.min_inlier_ratio = 0.7;
  for (const Pose& start : {Pose::planar(kTruth.x() + 1.0, kTruth.y(), kTruth.yaw()),
                            Pose::planar(kTruth.x() + 0.7, kTruth.y() - 0.7, kTruth.yaw() + 0.2)}) {
    const RefineResult r = refinePose(caster, rig, s.scans, start, 3, cfg);
    EXPECT_FALSE(r.accepted) << "from " << start.x() << " " << start.y();
    EXPECT_FALSE(r.reason.empty());
    EXPECT_TRUE(r.pose.isApprox(start));
  }
}

TEST(MclRefine, LargeCorrectionIsRefused) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const Scans s(caster, rig, kTruth, 0.0);
  const Pose start = Pose::planar(kTruth.x() + 0.03, kTruth.y() - 0.04, kTruth.yaw() + deg2rad(2.0));
  RefineConfig cfg;
  cfg.max_correction = 0.02;  // the 5 cm correction the scans ask for is beyond this
  RefineResult r = refinePose(caster, rig, s.scans, start, 3, cfg);
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(r.reason, "correction too large");
  EXPECT_TRUE(r.pose.isApprox(start));
  cfg = RefineConfig{};
  cfg.max_correction_yaw = deg2rad(1.0);  // and the 2 deg is beyond this
  r = refinePose(caster, rig, s.scans, start, 3, cfg);
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(r.reason, "correction too large");
}

TEST(MclRefine, BadArgumentsThrow) {
  const EmbreeCaster caster(asymmetricRoom());
  const Rig rig = scannerRig();
  const std::vector<float> r(rig.sensors[0].beams().size(), 1.f);
  const RefineScan bad{3, r, Pose()};
  EXPECT_THROW(refinePose(caster, rig, std::span(&bad, 1), Pose(), 3, RefineConfig{}), std::invalid_argument);
  const RefineScan ok{0, r, Pose()};
  EXPECT_THROW(refinePose(caster, rig, std::span(&ok, 1), Pose(), 4, RefineConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace polyloc::test
