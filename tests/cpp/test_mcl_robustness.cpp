// Bad and degenerate input: each handled without a crash, counted, with a defined status.
#include "mcl_fixtures.hpp"

#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/resample.hpp>

#include <gtest/gtest.h>

#include <limits>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_robustness {

using namespace polyloc;
using namespace polyloc::test;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

struct MclRobust : ::testing::Test {
  Mesh mesh = asymmetricRoom();
  EmbreeCaster caster{mesh};
  Rig rig = scannerRig();
  MclConfig cfg = [] {
    MclConfig c;
    c.particles = 500;
    return c;
  }();
  Localizer loc{caster, mesh, rig, cfg};
  Pose truth = Pose::planar(0.5, 0.5, 0.3);
  std::vector<float> scan(uint64_t step = 0) { return simulateScan(caster, rig.sensors[0], truth, 0.01, step); }
};

TEST_F(MclRobust, ScanBeforeInitIsRejected) {
  EXPECT_FALSE(loc.addScan(0, 0, scan()));
  EXPECT_EQ(loc.counters().scans_rejected, 1u);
  EXPECT_EQ(loc.estimate().status, MclStatus::Initialising);
}

TEST_F(MclRobust, AllMaxRangeAndAllNaNScansAreRejected) {
  loc.initPose(truth, planarCov(0.1, 0.05), 0);
  const size_t n = rig.sensors[0].beams().size();
  EXPECT_FALSE(loc.addScan(0, 1, std::vector<float>(n, float(rig.sensors[0].beams().range_max))));
  EXPECT_FALSE(loc.addScan(0, 2, std::vector<float>(n, kInf)));
  EXPECT_FALSE(loc.addScan(0, 3, std::vector<float>(n, kNaN)));
  EXPECT_FALSE(loc.addScan(0, 4, std::vector<float>(n, -1.f)));
  EXPECT_EQ(loc.counters().scans_rejected, 4u);
  EXPECT_EQ(loc.counters().updates, 0u);
  EXPECT_EQ(loc.estimate().status, MclStatus::Initialising);
  // Some NaN beams: the rest still count.
  auto r = scan();
  for (size_t b = 0; b < r.size(); b += 2) r[b] = kNaN;
  EXPECT_TRUE(loc.addScan(0, 5, r));
  EXPECT_EQ(loc.estimate().status, MclStatus::Tracking);
  EXPECT_LT(posErr(loc.estimate().pose, truth), 0.1);
}

TEST_F(MclRobust, WrongSensorOrSizeIsRejected) {
  loc.initPose(truth, planarCov(0.1, 0.05), 0);
  EXPECT_FALSE(loc.addScan(3, 1, scan()));
  EXPECT_FALSE(loc.addScan(0, 1, std::vector<float>(7, 1.f)));
  EXPECT_EQ(loc.counters().scans_rejected, 2u);
}

TEST_F(MclRobust, ZeroOdometryUpdatesOnlyOnce) {
  loc.initPose(truth, planarCov(0.1, 0.05), 0);
  for (int i = 0; i < 5; ++i) {
    loc.addOdometry(i * 100, Pose());
    const bool updated = loc.addScan(0, i * 100, scan(i));
    EXPECT_EQ(updated, i == 0) << i;
  }
  EXPECT_EQ(loc.counters().updates, 1u);
  EXPECT_EQ(loc.estimate().status, MclStatus::Tracking);
}

TEST_F(MclRobust, TimeGoingBackwards) {
  loc.initPose(truth, planarCov(0.1, 0.05), 0);
  loc.addOdometry(1000, Pose());
  loc.addOdometry(500, Pose::planar(5, 5, 1));  // older: ignored
  EXPECT_EQ(loc.counters().odometry_out_of_order, 1u);
  Pose bad = Pose::planar(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  loc.addOdometry(2000, bad);
  EXPECT_EQ(loc.counters().odometry_invalid, 1u);
  EXPECT_TRUE(loc.addScan(0, 1000, scan()));
  EXPECT_FALSE(loc.addScan(0, 900, scan(1)));  // stale scan
  EXPECT_EQ(loc.counters().scans_rejected, 1u);
  EXPECT_LT(posErr(loc.estimate().pose, truth), 0.1);  // the ignored odometry did not move it
}

TEST_F(MclRobust, EmptyMapRegionIsLost) {
  // Outside the room but within the map's margin: every particle floats over nothing.
  ASSERT_TRUE(loc.initPose(Pose::planar(9, 9, 0), planarCov(0.2, 0.1), 0));
  EXPECT_TRUE(loc.addScan(0, 1, scan()));
  EXPECT_EQ(loc.estimate().status, MclStatus::Lost);
  EXPECT_GT(loc.estimate().particles, 0u);
}

TEST_F(MclRobust, PosesAndOdometryOutsideTheDomainAreRefused) {
  ASSERT_TRUE(loc.initPose(truth, planarCov(0.1, 0.05), 0));
  ASSERT_TRUE(loc.addScan(0, 1, scan()));
  const Pose before = loc.estimate().pose;
  // Beyond the map's box plus 10 m, huge, or with spreads beyond their domain: nothing changes.
  EXPECT_FALSE(loc.initPose(Pose::planar(50, 50, 0), planarCov(0.2, 0.1), 2));
  EXPECT_FALSE(loc.initPose(Pose::planar(1e19, 0, 0), planarCov(0.2, 0.1), 2));
  EXPECT_FALSE(loc.initPose(truth, planarCov(1e19, 0.1), 2));
  EXPECT_FALSE(loc.initPose(truth, planarCov(0.1, 1e3), 2));
  EXPECT_EQ(loc.counters().poses_rejected, 4u);
  EXPECT_NE(loc.checkPose(Pose::planar(1e19, 0, 0), planarCov(0.2, 0.1)).value_or("").find("x is 1e+19"), std::string::npos);
  EXPECT_NE(loc.checkPose(truth, planarCov(1e19, 0.1)).value_or("").find("sigma x is 1e+19"), std::string::npos);
  // Odometry 1e19 m away is counted invalid and moves nothing; the filter goes on.
  loc.addOdometry(1000, Pose());
  loc.addOdometry(2000, Pose::planar(1e19, 0, 0));
  EXPECT_EQ(loc.counters().odometry_invalid, 1u);
  loc.addScan(0, 3000, scan(1));
  EXPECT_LT(posErr(loc.estimate().pose, before), 0.1);
}

TEST_F(MclRobust, ParticlesInsideWallsGetZeroWeight) {
  // Centred in the east wall (x in [4, 4.2]): in solid or too close to it.
  loc.initPose(Pose::planar(4.1, 0, 0), planarCov(0.01, 0.01), 0);
  loc.addScan(0, 1, scan());
  EXPECT_GE(loc.counters().particles_blocked, 500u);
  EXPECT_EQ(loc.counters().weights_collapsed, 1u);
  EXPECT_EQ(loc.estimate().status, MclStatus::Lost);
}

// A global round's particles x beams beyond the ranges kept at once go in blocks: the memory
// stays at kMaxHits ranges (a round of 10^7 particles x 1,000 beams would need 40 GB), and each
// particle's weight is the one it gets weighed alone.
TEST_F(MclRobust, ManyParticlesAreWeighedInBlocksOfBoundedMemory) {
  MclConfig all = cfg;
  all.beams_per_scan = 0;  // every valid beam
  BeamSensorModel model(caster, rig, all);
  const std::vector<float> ranges = scan();
  const size_t B = BeamSensorModel::selectBeams(rig.sensors[0].beams(), ranges, 0).size();
  ASSERT_GT(B, 100u);
  const size_t P = BeamSensorModel::kMaxHits / B + 5;  // two blocks
  ParticleSet ps;
  resizeParticles(ps, P);
  for (size_t p = 0; p < P; ++p) setParticle(ps, p, Pose::planar(0.5 + 1e-6 * double(p % 1000), 0.5, 0.3 + 1e-5 * double(p % 997)));
  std::vector<double> ll(P, 0.0);
  SensorFrame frame;
  frame.ranges = ranges;
  model.weigh(ps, frame, ll);
  EXPECT_LE(model.hitsCapacity(), BeamSensorModel::kMaxHits);
  for (const size_t p : {size_t(0), P / 2, BeamSensorModel::kMaxHits / B - 1, BeamSensorModel::kMaxHits / B, P - 1}) {
    BeamSensorModel alone(caster, rig, all);
    const ParticleSet one = gatherParticles(ps, {p});
    std::vector<double> l1(1, 0.0);
    alone.weigh(one, frame, l1);
    EXPECT_EQ(l1[0], ll[p]) << "particle " << p;
  }
}

TEST(MclParts, SystematicResampleAndKld) {
  std::vector<double> lw = {std::log(0.5), std::log(0.25), std::log(0.25), -std::numeric_limits<double>::infinity()};
  ASSERT_TRUE(normalizeLogWeights(lw));
  EXPECT_NEAR(effectiveSampleSize(lw), 1.0 / (0.25 + 0.0625 + 0.0625), 1e-9);
  const auto idx = systematicResample(lw, 8, CounterRng(3), 0);
  ASSERT_EQ(idx.size(), 8u);
  EXPECT_EQ(std::count(idx.begin(), idx.end(), 0u), 4);
  EXPECT_EQ(std::count(idx.begin(), idx.end(), 3u), 0);
  std::vector<double> dead(3, -std::numeric_limits<double>::infinity());
  EXPECT_FALSE(normalizeLogWeights(dead));
  EXPECT_NEAR(std::exp(dead[0]), 1.0 / 3, 1e-12);
  MclConfig c;
  EXPECT_EQ(kldParticleCount(1, c), c.min_particles);
  EXPECT_GT(kldParticleCount(200, c), kldParticleCount(20, c));
  EXPECT_LE(kldParticleCount(100000, c), c.max_particles);
}

TEST(MclParts, BeamLikelihoodPrefersTheExpectedRange) {
  BeamModel m;
  const double at = BeamSensorModel::logLikelihood(3.0, 3.0, 10, m);
  const double off = BeamSensorModel::logLikelihood(3.0, 3.2, 10, m);
  const double outside = BeamSensorModel::logLikelihood(3.0, std::numeric_limits<double>::infinity(), 10, m);
  EXPECT_GT(at, off);
  EXPECT_GT(off, outside);
  EXPECT_TRUE(std::isfinite(outside));
}

}  // namespace polyloc::t_mcl_robustness
