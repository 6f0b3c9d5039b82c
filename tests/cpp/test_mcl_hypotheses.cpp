// Global hypotheses (hypotheses.hpp): distinct modes of a cloud, their refinement against the
// mesh, planting them back; and the blocked-particle guard (blocked_max_mass).
#include "mcl_fixtures.hpp"

#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/hypotheses.hpp>
#include <polyloc/mcl/refine.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_hypotheses {

using namespace polyloc;
using namespace polyloc::test;

TEST(MclHypotheses, DistinctModesAreSeparatedAndBestFirst) {
  ParticleSet ps = particlesAt({Pose::planar(0, 0, 0), Pose::planar(0.1, 0, 0), Pose::planar(0, 0, 1.0),
                                Pose::planar(2, 0, 0), Pose::planar(3, 0, 0)});
  ps.logw = {-1.0, -0.5, -2.0, -3.0, -std::numeric_limits<double>::infinity()};
  const auto m = distinctModes(ps, 10, 0.5, 0.35);
  // 1 is best; 0 is within 0.5 m and the same yaw, so merged; 2 is turned by 1 rad: a mode of its
  // own; 3 is 2 m away; 4 has weight zero.
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0], 1u);
  EXPECT_EQ(m[1], 2u);
  EXPECT_EQ(m[2], 3u);
  EXPECT_EQ(distinctModes(ps, 2, 0.5, 0.35).size(), 2u);
}

TEST(MclHypotheses, RefineModesKeepsThePlaceThatFits) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  const Pose truth = Pose::planar(-1.0, 0.5, 0.3);
  const std::vector<float> r = simulateScan(caster, rig.sensors[0], truth, 0.005, 1);
  const RefineScan scan{0, r, Pose()};
  // One mode 0.25 m and 6 deg off the truth, one at the room's mirror pose (the cabinet and the
  // bin do not fit there), one far off in yaw.
  ParticleSet ps = particlesAt({Pose::planar(-0.8, 0.35, 0.4), Pose::planar(1.0, -0.5, 0.3 + M_PI),
                                Pose::planar(0.5, 1.0, -1.5)});
  ps.logw = {-3.0, -1.0, -2.0};  // the best-weighted mode is the wrong one
  GlobalHypotheses cfg;
  const std::vector<Hypothesis> h = refineModes(caster, rig, std::span(&scan, 1), ps, cfg, RefineConfig{});
  ASSERT_EQ(h.size(), 1u);
  EXPECT_LT(posErr(h[0].pose, truth), 0.01);
  EXPECT_LT(yawErrDeg(h[0].pose, truth), 0.3);
  EXPECT_GT(h[0].inlier_ratio, 0.95);
}

TEST(MclHypotheses, PlantReplacesTheLightestAtTheBestWeight) {
  ParticleSet ps = particlesAt(std::vector<Pose>(10, Pose::planar(5, 5, 0)));
  for (size_t i = 0; i < 10; ++i) ps.logw[i] = -double(i);
  GlobalHypotheses cfg;
  cfg.particles = 2;
  cfg.spread_xy = 0.01;
  const std::vector<Hypothesis> hyps = {{Pose::planar(1, 1, 0.5), 0.9, 0.01}, {Pose::planar(-1, 2, -0.5), 0.9, 0.01}};
  EXPECT_EQ(plantHypotheses(ps, hyps, cfg, CounterRng(1), 7), 4u);
  for (size_t i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(ps.x[i], 5.0) << i;  // the heavier six stay
  for (size_t i = 6; i < 10; ++i) {
    EXPECT_DOUBLE_EQ(ps.logw[i], 0.0) << i;
    const Hypothesis& h = hyps[(i - 6) % 2];
    EXPECT_LT(posErr(ps.pose(i), h.pose), 0.05) << i;
  }
  // Never more than half the set.
  cfg.particles = 100;
  EXPECT_EQ(plantHypotheses(ps, hyps, cfg, CounterRng(1), 8), 5u);
}

TEST(MclHypotheses, BlockedParticlesHoldingMostWeightAreKept) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  MclConfig cfg;
  FreeFloor floor(caster, mesh, cfg);
  // Three particles 0.1 m from the cabinet's west face (x = 2.6), one in the open.
  ParticleSet ps = particlesAt({Pose::planar(2.5, 2.0, 0), Pose::planar(2.5, 2.1, 0), Pose::planar(2.5, 2.2, 0),
                                Pose::planar(0, 0, 0)});
  ParticleSet a = ps;
  BlockedResult r = floor.zeroBlocked(a, 0.5);  // 3/4 of the weight blocked: the robot is there
  EXPECT_EQ(r.zeroed, 0u);
  EXPECT_EQ(r.ignored, 3u);
  EXPECT_TRUE(std::isfinite(a.logw[0]));
  ParticleSet b = ps;
  b.logw = {-5.0, -5.0, -5.0, 0.0};  // the blocked ones are light: zeroed
  r = floor.zeroBlocked(b, 0.5);
  EXPECT_EQ(r.zeroed, 3u);
  EXPECT_FALSE(std::isfinite(b.logw[1]));
  EXPECT_TRUE(std::isfinite(b.logw[3]));
}

// Along a corridor every round finds several places; the one that keeps fitting as the robot
// moves leads a better single fit elsewhere, which must out-fit it again to take the lead; a place
// not found falls behind.
TEST(MclHypotheses, TrackedPlacesAccumulateAndFollowOdometry) {
  std::vector<TrackedPlace> places;
  const double lead = 0.2, drop = 0.6;
  const Pose step = Pose::planar(1.0, 0, 0);  // the robot drove 1 m ahead between rounds
  // Round 1: the truth at (0, 0) and a wrong place at (10, 5), heading +x.
  trackPlaces(places, std::vector<Hypothesis>{{Pose::planar(0, 0, 0), 0.85, 0.03}, {Pose::planar(10, 5, 0), 0.8, 0.03}}, Pose(), lead, drop);
  ASSERT_EQ(places.size(), 2u);
  EXPECT_TRUE(contested(places, lead));  // 0.05 apart after one round
  // Rounds 2 and 3: the truth found again 1 m on (a few cm off the odometry), the wrong place not;
  // a newcomer fits better than the truth in round 3 alone.
  trackPlaces(places, std::vector<Hypothesis>{{Pose::planar(1.03, 0.02, 0.01), 0.9, 0.03}}, step, lead, drop);
  EXPECT_FALSE(contested(places, lead));  // the wrong place missed a round: 0.25 behind
  trackPlaces(places, std::vector<Hypothesis>{{Pose::planar(2.0, 0, 0), 0.88, 0.03}, {Pose::planar(-20, 3, 3.0), 0.97, 0.02}}, step, lead, drop);
  // (10, 5) missed twice: 0.65, 0.36 behind the leader, kept (forgotten beyond `drop`).
  ASSERT_EQ(places.size(), 3u);
  EXPECT_NEAR(places[1].deficit, lead + 0.05 + lead + lead, 1e-9);
  EXPECT_EQ(places[1].missed, 2u);
  const TrackedPlace* best = bestPlace(places);
  ASSERT_NE(best, nullptr);
  EXPECT_NEAR(best->pose.x(), 2.0, 1e-9);
  EXPECT_NEAR(best->deficit, lead + 0.0 + 0.0 + (0.97 - 0.88), 1e-9);
  EXPECT_EQ(best->rounds, 3u);
  EXPECT_EQ(best->missed, 0u);
  // The newcomer joined `lead` behind the leader of round 2 (0.2) and fitted best: 0.4 against
  // 0.29, within the lead, contested.
  EXPECT_TRUE(contested(places, lead));
  // Unmatched this round: carried by odometry, every place a lead further behind.
  trackPlaces(places, {}, step, lead, drop);
  EXPECT_NEAR(bestPlace(places)->pose.x(), 3.0, 1e-9);
  EXPECT_EQ(bestPlace(places)->missed, 1u);
  EXPECT_EQ(bestPlace(std::vector<TrackedPlace>{}), nullptr);
  EXPECT_FALSE(contested(std::vector<TrackedPlace>{}, lead));
}

// A place far behind is forgotten; two fits of one place never contest each other.
TEST(MclHypotheses, PlacesFarBehindAreDroppedAndOnePlaceIsNoContest) {
  std::vector<TrackedPlace> places{{Pose::planar(0, 0, 0), 0.0, 3, 0}, {Pose::planar(30, 0, 0), 0.5, 3, 0}};
  trackPlaces(places, std::vector<Hypothesis>{{Pose::planar(0, 0, 0), 0.9, 0.03}, {Pose::planar(30, 0, 0), 0.75, 0.03}}, Pose(), 0.2, 0.6);
  ASSERT_EQ(places.size(), 1u);  // 0.65 behind
  EXPECT_NEAR(places[0].pose.x(), 0.0, 1e-9);
  const std::vector<TrackedPlace> twins{{Pose::planar(0, 0, 0), 0.0, 2, 0}, {Pose::planar(0.4, 0, 0.1), 0.05, 2, 0}};
  EXPECT_FALSE(contested(twins, 0.2));
  const std::vector<TrackedPlace> rivals{{Pose::planar(0, 0, 0), 0.0, 2, 0}, {Pose::planar(0, 0, M_PI), 0.05, 2, 0}};
  EXPECT_TRUE(contested(rivals, 0.2));  // the corridor seen both ways
}

}  // namespace polyloc::t_mcl_hypotheses
