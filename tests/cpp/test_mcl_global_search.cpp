// The global search (global_search.hpp): the screen finds the place the cloud missed, the places
// are tracked over rounds by odometry and forgotten at a new prior, and a room that looks the same
// both ways is ambiguous.
#include "mcl_fixtures.hpp"

#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/global_search.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_global_search {

using namespace polyloc;
using namespace polyloc::test;

// A cloud of a few particles, all at one wrong place: only the screen can find the robot.
ParticleSet wrongCloud() { return particlesAt({Pose::planar(1.5, -1.5, 2.0), Pose::planar(1.6, -1.5, 2.1)}); }

TEST(MclGlobalSearch, TheScreenFindsThePlaceAndRoundsTrackIt) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg;
  FreeFloor floor(caster, mesh, cfg);
  GlobalSearch search(caster, caster, mesh, rig, cfg);
  const ParticleSet ps = wrongCloud();
  const Pose truth = Pose::planar(-1.0, 0.5, 0.3);
  const std::vector<float> r1 = simulateScan(caster, rig.sensors[0], truth, 0.005, 1);
  const RefineScan s1{0, r1, Pose()};
  const GlobalRound a = search.round(std::span(&s1, 1), ps, Pose(), floor, CounterRng(1), 7);
  ASSERT_TRUE(a.best.has_value());
  // Refined against the mesh: within 1 cm and 0.5 deg (measured: about 1 mm and 0.05 deg).
  EXPECT_LT(posErr(*a.best, truth), 0.01);
  EXPECT_LT(yawErrDeg(*a.best, truth), 0.5);
  EXPECT_FALSE(a.ambiguous);  // the cabinet and the bin break the room's symmetry
  for (const Hypothesis& h : a.hypotheses) EXPECT_LT(posErr(h.pose, truth), 0.05);  // no wrong place fits
  const size_t places = search.trackedPlaces();
  EXPECT_GE(places, 1u);
  // The robot drives 0.4 m on: the next round's best place is where the odometry took the first.
  const Pose moved = Pose::planar(0.4, 0, 0);
  const Pose truth2 = truth * moved;
  const std::vector<float> r2 = simulateScan(caster, rig.sensors[0], truth2, 0.005, 2);
  const RefineScan s2{0, r2, Pose()};
  const GlobalRound b = search.round(std::span(&s2, 1), ps, moved, floor, CounterRng(1), 7);
  ASSERT_TRUE(b.best.has_value());
  EXPECT_LT(posErr(*b.best, truth2), 0.01);
  EXPECT_EQ(search.trackedPlaces(), places);  // the same place, matched, not a new one
  search.restart();
  EXPECT_EQ(search.trackedPlaces(), 0u);
}

TEST(MclGlobalSearch, ARoomThatLooksTheSameBothWaysIsAmbiguous) {
  const Mesh mesh = boxRoom(3.f, 1.5f, 2.5f, 0.2f);
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  MclConfig cfg;
  FreeFloor floor(caster, mesh, cfg);
  GlobalSearch search(caster, caster, mesh, rig, cfg);
  const Pose truth = Pose::planar(1.2, 0.4, 0.3);
  const Pose mirror = Pose::planar(0, 0, M_PI) * truth;
  const std::vector<float> r = simulateScan(caster, rig.sensors[0], truth, 0.005, 1);
  const RefineScan s{0, r, Pose()};
  const GlobalRound g = search.round(std::span(&s, 1), wrongCloud(), Pose(), floor, CounterRng(1), 7);
  EXPECT_TRUE(g.ambiguous);
  bool at_truth = false, at_mirror = false;
  for (const Hypothesis& h : g.hypotheses) {
    at_truth = at_truth || (posErr(h.pose, truth) < 0.02 && yawErrDeg(h.pose, truth) < 1);
    at_mirror = at_mirror || (posErr(h.pose, mirror) < 0.02 && yawErrDeg(h.pose, mirror) < 1);
  }
  EXPECT_TRUE(at_truth && at_mirror);
  // Near a prediction, within a heading window: only the place there (local recovery's question).
  const std::vector<Pose> near{Pose::planar(1.3, 0.3, 0)};
  const std::vector<Hypothesis> local = search.fittingModes(std::span(&s, 1), wrongCloud(), near, deg2rad(20));
  bool found = false;
  for (const Hypothesis& h : local) found = found || (posErr(h.pose, truth) < 0.02 && yawErrDeg(h.pose, truth) < 1);
  EXPECT_TRUE(found);
}

}  // namespace polyloc::t_mcl_global_search
