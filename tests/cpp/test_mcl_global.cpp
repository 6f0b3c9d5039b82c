// Global localisation from a uniform prior over the free floor, and recovery from kidnapping
// by augmented-MCL injection.
#include "mcl_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_global {

using namespace polyloc;
using namespace polyloc::test;

MclConfig globalConfig() {
  MclConfig c;
  c.global_particles = 20000;
  c.beam.sigma_hit = 0.1;
  c.beam.log_scale = 0.1;  // tempered: the sparse cloud must not collapse onto a lucky particle
  return c;
}

TEST(MclGlobal, ParticlesOnlyOnFreeFloor) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg = globalConfig();
  cfg.global_particles = 5000;
  cfg.clearance = 0.25;
  Localizer loc(caster, mesh, rig, cfg);
  loc.initGlobal(0);
  const ParticleSet& ps = loc.particles();
  ASSERT_EQ(ps.size(), 5000u);
  for (size_t i = 0; i < ps.size(); ++i) {
    ASSERT_NEAR(ps.z[i], 0.0, 1e-4) << i;  // on the floor, not on the cabinet or the bin
    ASSERT_LE(std::abs(ps.x[i]), 4.0 - 0.25 + 1e-6) << i;
    ASSERT_LE(std::abs(ps.y[i]), 3.0 - 0.25 + 1e-6) << i;
    // Not in the cabinet ([2.6, 3.8] x [1.6, 2.8]) nor closer than robot_radius to it.
    const double dx = std::max({0.0, 2.6 - ps.x[i], ps.x[i] - 3.8}), dy = std::max({0.0, 1.6 - ps.y[i], ps.y[i] - 2.8});
    ASSERT_GE(std::hypot(dx, dy), 0.25 - 1e-3) << i;
  }
  EXPECT_EQ(loc.estimate().status, MclStatus::Initialising);
}

TEST(MclGlobal, ConvergesFromUniformPrior) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  Localizer loc(caster, mesh, rig, globalConfig());
  loc.initGlobal(0);
  const auto truth = loopTrajectory(40);
  drive(loc, caster, rig, truth);
  const MclEstimate e = loc.estimate();
  const double pe = posErr(e.pose, truth.back()), ye = yawErrDeg(e.pose, truth.back());
  std::printf("[mcl] global: pos err %.4f m, yaw err %.3f deg, n %zu, status %s\n", pe, ye, e.particles,
              toString(e.status));
  EXPECT_LT(pe, 0.2);
  EXPECT_LT(ye, 5.0);
  EXPECT_EQ(e.status, MclStatus::Tracking);
}

TEST(MclGlobal, EstimatesSayHowFarTheSearchIs) {
  // polylocd's health (flags bit 3) and log say a global search runs and which round it is at.
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  const MclConfig cfg = globalConfig();
  Localizer loc(caster, mesh, rig, cfg);
  loc.initGlobal(0);
  EXPECT_EQ(loc.estimate().global_round, 0u);  // no round closed yet
  EXPECT_TRUE(loc.searching());
  const auto truth = loopTrajectory(40);
  const Pose map_T_odom = Pose::planar(0.7, -0.3, 0.5);
  std::vector<uint32_t> rounds;
  for (size_t i = 0; i < truth.size(); ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    loc.addOdometry(t, map_T_odom.inverse() * truth[i]);
    if (loc.addScan(0, t, simulateScan(caster, rig.sensors[0], truth[i], 0.01, i))) rounds.push_back(loc.estimate().global_round);
  }
  // 1, 2, ..., k (at least the coarse rounds, at most the most), then 0 for good.
  ASSERT_GT(rounds.size(), cfg.global_max_coarse_rounds + 2);
  size_t k = 0;
  while (k < rounds.size() && rounds[k] == k + 1) ++k;
  EXPECT_GE(k, cfg.global_coarse_rounds);
  EXPECT_LE(k, cfg.global_max_coarse_rounds);
  for (size_t i = k; i < rounds.size(); ++i) EXPECT_EQ(rounds[i], 0u) << i;
  EXPECT_EQ(loc.estimate().status, MclStatus::Tracking);
  EXPECT_FALSE(loc.searching());
  loc.initPose(truth.back(), planarCov(0.05, 0.02), int64_t(truth.size()) * 100'000'000);
  EXPECT_FALSE(loc.searching());
}

TEST(MclGlobal, RecoversFromKidnapping) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg = globalConfig();
  cfg.particles = 2000;
  cfg.alpha_slow = 0.05;  // the long-term average settles within the 20 updates before the jump
  cfg.alpha_fast = 0.3;
  Localizer loc(caster, mesh, rig, cfg);
  auto truth = loopTrajectory(80);
  loc.initPose(truth[0], planarCov(0.05, 0.02), 0);
  // From step 20 on the robot is somewhere else, but odometry does not know.
  const Pose jump = Pose::planar(2.5, -1.0, 0.0);  // stays in the room
  for (size_t i = 20; i < truth.size(); ++i) truth[i] = jump * truth[i];
  const Pose map_T_odom;
  size_t recovered_at = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    const Pose odom = i < 20 ? truth[i] : jump.inverse() * truth[i];
    loc.addOdometry(t, odom);
    loc.addScan(0, t, simulateScan(caster, rig.sensors[0], truth[i], 0.01, i));
    const MclEstimate e = loc.estimate();
    if (i >= 20 && !recovered_at && posErr(e.pose, truth[i]) < 0.2 && yawErrDeg(e.pose, truth[i]) < 5) recovered_at = i;
  }
  std::printf("[mcl] kidnap: recovered after %zu updates, injected %llu\n", recovered_at ? recovered_at - 20 : 999,
              (unsigned long long)loc.counters().injected);
  EXPECT_GT(loc.counters().injected, 0u);
  EXPECT_GT(recovered_at, 0u);
  EXPECT_LE(recovered_at, 20u + 50u);
  EXPECT_LT(posErr(loc.estimate().pose, truth.back()), 0.2);
}

// A prior far too sparse to hold a particle near the truth (200 over the 45 m2 room: about one
// within 0.5 m and 15 deg of any pose, most of those too far off to weigh well): scan screening
// still hands the refinement a candidate near it, and the round reports the best refined place.
TEST(MclGlobal, FirstRoundReportsTheBestRefinedPlace) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg = globalConfig();
  cfg.global_particles = 200;
  cfg.hypotheses.fresh = 0;
  for (const Pose& truth : {Pose::planar(1.2, -0.8, 2.5), Pose::planar(-2.0, 1.0, -0.7), Pose::planar(0.5, 2.0, 1.9)}) {
    Localizer loc(caster, mesh, rig, cfg);
    loc.initGlobal(0);
    loc.addScan(0, 0, simulateScan(caster, rig.sensors[0], truth, 0.01, 1));
    const MclEstimate e = loc.estimate();
    EXPECT_LT(posErr(e.pose, truth), 0.05) << truth.x() << " " << truth.y() << " " << toString(e.status);
    EXPECT_LT(yawErrDeg(e.pose, truth), 1.0) << truth.x() << " " << truth.y();
  }
}

}  // namespace polyloc::t_mcl_global
