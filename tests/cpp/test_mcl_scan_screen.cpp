// Scan screening (scan_screen.hpp): candidates of the free floor scored by where a scan's level
// beams land on the map's 2D distance transform.
#include "mcl_fixtures.hpp"

#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/scan_screen.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_scan_screen {

using namespace polyloc;
using namespace polyloc::test;


struct Room {
  Mesh mesh = asymmetricRoom();
  EmbreeCaster caster{mesh};
  Rig rig = scannerRig();
  MclConfig cfg;
  std::vector<Pose> positions;
  Room() {
    FreeFloor floor(caster, mesh, cfg);
    positions = floor.sampleFree(3000, CounterRng(5), 11);
  }
};


TEST(ScanScreen, TheTruePoseIsTheBestCandidate) {
  Room room;
  ScanScreenConfig sc;
  const ScanScreen screen(room.mesh, 0.2, sc);
  // Three places of the room; the cabinet and the bin make each unique, so the best candidate is
  // the truth, up to the candidate grid (positions about 0.1 m apart here, headings 5 deg).
  for (const Pose& truth : {Pose::planar(-1.0, 0.5, 0.3), Pose::planar(1.2, -0.8, 2.5), Pose::planar(0.3, 1.5, -1.2)}) {
    const std::vector<float> r = simulateScan(room.caster, room.rig.sensors[0], truth, 0.01, 1);
    const RefineScan scan{0, r, Pose()};
    const std::vector<Pose> best = screen.best(room.rig, std::span(&scan, 1), room.positions, 0.5, 0.35);
    ASSERT_EQ(best.size(), sc.keep);
    EXPECT_LT(posErr(best[0], truth), 0.25) << truth.x() << " " << truth.y();
    EXPECT_LT(yawErrDeg(best[0], truth), 5.0) << truth.x() << " " << truth.y();
  }
}

TEST(ScanScreen, CandidatesAreDistinctAndAtMostKeep) {
  Room room;
  ScanScreenConfig sc;
  sc.keep = 10;
  const ScanScreen screen(room.mesh, 0.2, sc);
  const Pose truth = Pose::planar(-1.0, 0.5, 0.3);
  const std::vector<float> r = simulateScan(room.caster, room.rig.sensors[0], truth, 0.01, 1);
  const RefineScan scan{0, r, Pose()};
  const std::vector<Pose> best = screen.best(room.rig, std::span(&scan, 1), room.positions, 0.5, 0.35);
  ASSERT_EQ(best.size(), 10u);
  for (size_t i = 0; i < best.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      EXPECT_TRUE(posErr(best[i], best[k]) >= 0.5 || yawErrDeg(best[i], best[k]) >= rad2deg(0.35)) << i << " " << k;
}

TEST(ScanScreen, NoLevelBeamNoCandidate) {
  Room room;
  const ScanScreen screen(room.mesh, 0.2, ScanScreenConfig{});
  const Pose truth = Pose::planar(-1.0, 0.5, 0.3);
  // The scanner tilted 45 deg down sees the floor only: nothing to screen with.
  Rig tilted = room.rig;
  tilted.sensors[0].mount = Pose::fromXYZRPY(0.1, 0, 0.2, 0, deg2rad(45.0), 0);
  const std::vector<float> r = simulateScan(room.caster, tilted.sensors[0], truth, 0.01, 1);
  const RefineScan scan{0, r, Pose()};
  EXPECT_TRUE(screen.best(tilted, std::span(&scan, 1), room.positions, 0.5, 0.35).empty());
  // Nor without positions, or with screening off.
  const RefineScan level{0, simulateScan(room.caster, room.rig.sensors[0], truth, 0.01, 1), Pose()};
  EXPECT_TRUE(screen.best(room.rig, std::span(&level, 1), {}, 0.5, 0.35).empty());
  ScanScreenConfig off;
  off.keep = 0;
  EXPECT_TRUE(ScanScreen(room.mesh, 0.2, off).best(room.rig, std::span(&level, 1), room.positions, 0.5, 0.35).empty());
}

}  // namespace polyloc::t_mcl_scan_screen
