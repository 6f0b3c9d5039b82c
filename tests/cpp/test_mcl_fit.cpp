// The pieces that let the filter hold on maps that are centimetres off: the fit check (beams
// seen through the map's walls say "wrong place", beams cut short by a person do not), the
// exhaustive pose search before the refinement, the refinement on a map whose walls are steps of
// grid cells, and the robot's clearance taken from its footprint.
#include "mcl_fixtures.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/map/extrude.hpp>
#include <polyloc/mcl/fit_check.hpp>
#include <polyloc/mcl/pose_search.hpp>
#include <polyloc/mcl/refine.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

namespace polyloc::test::t_mcl_fit {  // the file's own: the suite is compiled in batches (unity build)
namespace {

struct Room {
  Mesh mesh = asymmetricRoom();
  EmbreeCaster caster{mesh};
  Rig rig = scannerRig();
  Pose truth = Pose::planar(-0.8, 0.4, 0.3);
  std::vector<float> ranges = simulateScan(caster, rig.sensors[0], truth, 0.01, 1);
  RefineScan scan() const { return RefineScan{0, ranges, Pose()}; }
  // The rig and a second scanner pitched 30 deg down: every beam at least 25 deg below level.
  Rig withTiltedScanner() const {
    Rig out = rig;
    PlanarScannerSpec down = std::get<PlanarScannerSpec>(rig.sensors[0].spec);
    down.fov_rad = deg2rad(60.0);
    out.add(Sensor{"tilted", down, Pose::fromXYZRPY(0.1, 0, 0.4, 0, deg2rad(30.0), 0)}, "");
    return out;
  }
};

TEST(FitCheck, TheRightPlaceIsExplainedAWrongOneSeenThrough) {
  Room r;
  const RefineScan s = r.scan();
  const ScanFit at = checkFit(r.caster, r.rig, std::span(&s, 1), r.truth, 0.3, 0);
  EXPECT_GT(at.beams, 200u);
  EXPECT_GT(at.explainedShare(), 0.99);
  EXPECT_EQ(at.longer, 0u);
  // 1.5 m and 40 deg off: many beams end beyond the walls the map puts on their rays.
  const ScanFit off = checkFit(r.caster, r.rig, std::span(&s, 1), Pose::planar(1.0, -1.0, 1.0), 0.3, 0);
  EXPECT_GT(off.seenThrough(), 0.25) << off.longer << " of " << off.beams;
}

TEST(FitCheck, PeopleInFrontShortenBeamsAndContradictNothing) {
  Room r;
  std::vector<float> ranges = r.ranges;
  for (size_t b = 60; b < 160; ++b) ranges[b] = std::min(ranges[b], 0.6f);  // a person 0.6 m away
  const RefineScan s{0, ranges, Pose()};
  const ScanFit fit = checkFit(r.caster, r.rig, std::span(&s, 1), r.truth, 0.3, 0);
  EXPECT_EQ(fit.longer, 0u);
  EXPECT_GT(fit.shorter, 90u);
  EXPECT_DOUBLE_EQ(fit.seenThrough(), 0.0);
}

// The map holds what is not there now (a grid of end points keeps every person the mapping run
// saw, and doors closed then): beams at the right place go past it and end on the wall behind.
// They are counted apart, not seen through; at a wrong place beams still end where the map has
// nothing, and the round is contradicted.
TEST(FitCheck, BeamsPastWhatTheMapHoldsAndIsGoneAreNotSeenThrough) {
  Room r;  // the scan of the room as it is now
  Mesh then = asymmetricRoom();
  mapgen::MeshBuilder b(then);
  for (const auto& [x, y] : {std::pair{0.4f, 1.0f}, std::pair{0.7f, -0.2f}, std::pair{-0.2f, -0.9f}})
    b.box({x - 0.2f, y - 0.2f, 0.f}, {x + 0.2f, y + 0.2f, 1.7f}, "person");  // people of the mapping run
  b.box({-1.35f, -0.6f, 0.f}, {-1.25f, 1.2f, 2.0f}, "door");              // a partition closed then, open now
  EmbreeCaster map_then(then);
  const RefineScan s = r.scan();
  const double share = MclConfig{}.fit.past_share;
  const ScanFit with = checkFit(map_then, r.rig, std::span(&s, 1), r.truth, 0.3, 0, share);
  const ScanFit without = checkFit(map_then, r.rig, std::span(&s, 1), r.truth, 0.3, 0);
  EXPECT_GT(without.seenThrough(), 0.25) << "the phantoms must hide a share of the room for the test to mean anything";
  EXPECT_EQ(with.past_surface, without.longer);
  EXPECT_EQ(with.longer, 0u);
  EXPECT_EQ(with.explained, without.explained);
  // 1.5 m and 40 deg off, in the same map: beams through its walls end on surfaces only by
  // chance, and the frame is still contradicted.
  const ScanFit off = checkFit(map_then, r.rig, std::span(&s, 1), Pose::planar(1.0, -1.0, 1.0), 0.3, 0, share);
  EXPECT_GT(off.seenThrough(), 0.25) << off.longer << " of " << off.beams;
}

// A scanner tilted down sees the floor, which a wrong place on the same floor explains as well:
// its beams are not compared, and do not dilute the level scanner's share seen through walls.
TEST(FitCheck, TiltedBeamsAreNotCompared) {
  Room r;
  const Rig rig = r.withTiltedScanner();
  const std::vector<float> floor_ranges = simulateScan(r.caster, rig.sensors[1], r.truth, 0.01, 1);
  const std::vector<RefineScan> scans{r.scan(), RefineScan{1, floor_ranges, Pose()}};
  const Pose wrong = Pose::planar(1.0, -1.0, 1.0);
  const ScanFit level_only = checkFit(r.caster, r.rig, std::span(scans.data(), 1), wrong, 0.3, 0);
  const ScanFit both = checkFit(r.caster, rig, scans, wrong, 0.3, 0);
  EXPECT_EQ(both.beams, level_only.beams);
  EXPECT_DOUBLE_EQ(both.seenThrough(), level_only.seenThrough());
  EXPECT_EQ(checkFit(r.caster, rig, std::span(scans.data() + 1, 1), wrong, 0.3, 0).beams, 0u);
}

TEST(PoseSearch, FindsThePoseFromCentimetresAndDegreesOff) {
  Room r;
  const RefineScan s = r.scan();
  const Pose start = Pose::planar(r.truth.x() + 0.07, r.truth.y() - 0.06, r.truth.yaw() + deg2rad(1.5));
  const PoseSearchResult res = searchPose(r.caster, r.rig, std::span(&s, 1), start, PoseSearch{});
  EXPECT_LT(posErr(res.pose, r.truth), 0.015);
  EXPECT_LT(yawErrDeg(res.pose, r.truth), 0.3);
  EXPECT_EQ(res.candidates, 5u * 5 * 5 + 5u * 5 * 5);  // coarse +-10 cm at 5 cm, +-2 deg at 1 deg; then fine
  EXPECT_GT(res.inliers, res.beams * 9 / 10);
  // No window: the given pose.
  PoseSearch none;
  none.window_xy = none.window_yaw = 0;
  EXPECT_TRUE(searchPose(r.caster, r.rig, std::span(&s, 1), start, none).pose.isApprox(start));
}

// The search is planar: a tilted scanner's floor hits fit every candidate alike and only cost
// rays (the lab rig's four tilted URGs were three quarters of the search's rays, polylocd's pose
// latency p50 14.9 -> 12.3 ms without them). Level beams alone are scored, all beams when a
// round has no level one.
TEST(PoseSearch, ScoresLevelBeamsOnly) {
  Room r;
  const Rig rig = r.withTiltedScanner();
  const std::vector<float> floor_ranges = simulateScan(r.caster, rig.sensors[1], r.truth, 0.01, 1);
  const std::vector<RefineScan> scans{r.scan(), RefineScan{1, floor_ranges, Pose()}};
  const Pose start = Pose::planar(r.truth.x() + 0.07, r.truth.y() - 0.06, r.truth.yaw() + deg2rad(1.5));
  const PoseSearchResult level = searchPose(r.caster, r.rig, std::span(scans.data(), 1), start, PoseSearch{});
  const PoseSearchResult both = searchPose(r.caster, rig, scans, start, PoseSearch{});
  EXPECT_EQ(both.beams, level.beams);
  EXPECT_TRUE(both.pose.isApprox(level.pose));
  const PoseSearchResult tilted = searchPose(r.caster, rig, std::span(scans.data() + 1, 1), start, PoseSearch{});
  EXPECT_EQ(tilted.beams, PoseSearch{}.beams_per_scan);  // no level beam: all of them
}

// The spread of the search's likelihood (Olson's covariance from the scores): along a bare
// corridor the scans do not fix the position and the spread is as wide as the window; across it,
// and in a room, it is a cell or less. The Hessian of one minimum says neither.
TEST(PoseSearch, SpreadIsWideAlongACorridorAndTightInARoom) {
  Mesh m = boxRoom(10.f, 1.f, 2.5f, 0.2f);  // 20 m by 2 m, its ends beyond the scanner's range
  const EmbreeCaster caster(m);
  const Rig rig = scannerRig(6.0);
  const Pose truth = Pose::planar(0.3, 0.1, 0.05);
  const std::vector<float> ranges = simulateScan(caster, rig.sensors[0], truth, 0.01, 1);
  const RefineScan s{0, ranges, Pose()};
  PoseSearch o;
  o.window_xy = 0.3;
  o.spread_beams = 18;
  const PoseSearchResult corridor = searchPose(caster, rig, std::span(&s, 1), truth, o);
  EXPECT_GT(std::sqrt(corridor.spread(0, 0)), 0.12);  // flat over +-0.3 m: 0.17 m std for a uniform
  EXPECT_LT(std::sqrt(corridor.spread(1, 1)), 0.02);
  EXPECT_LT(std::sqrt(corridor.spread(2, 2)), deg2rad(0.6));
  Room r;
  const RefineScan rs = r.scan();
  const PoseSearchResult room = searchPose(r.caster, r.rig, std::span(&rs, 1), r.truth, o);
  EXPECT_LT(std::sqrt(room.spread(0, 0)), 0.02);
  EXPECT_LT(std::sqrt(room.spread(1, 1)), 0.02);
  o.spread_beams = 0;
  EXPECT_TRUE(searchPose(caster, rig, std::span(&s, 1), truth, o).spread.isZero());
}

// A room extruded from a 5 cm grid whose walls run at 30 deg to the cells: steps of cells, the
// correspondences' normals flip between iterations. The refinement still settles within a cell.
TEST(Refine, SettlesOnAStaircaseWall) {
  OccupancyGrid g;
  g.resolution = 0.05;
  g.origin_x = g.origin_y = -5;
  g.resize(200, 200, OccupancyGrid::kFree);
  const double c = std::cos(deg2rad(30.0)), s = std::sin(deg2rad(30.0));
  for (size_t y = 0; y < g.height; ++y)
    for (size_t x = 0; x < g.width; ++x) {
      const double wx = g.origin_x + (x + 0.5) * g.resolution, wy = g.origin_y + (y + 0.5) * g.resolution;
      const double u = c * wx + s * wy, v = -s * wx + c * wy;  // room frame
      const bool wall = (std::abs(u) > 3.0 && std::abs(u) < 3.2 && std::abs(v) < 3.2) ||
                        (std::abs(v) > 2.0 && std::abs(v) < 2.2 && std::abs(u) < 3.2) ||
                        (std::abs(u - 1.0) < 0.3 && std::abs(v - 1.0) < 0.3);  // a pillar: no symmetry
      if (wall) g.at(x, y) = OccupancyGrid::kOccupied;
    }
  const Mesh mesh = extrudeGrid(g);
  EmbreeCaster caster(mesh);
  const Rig rig = scannerRig();
  const Pose truth = Pose::planar(-0.5, 0.3, 0.4);
  const auto ranges = simulateScan(caster, rig.sensors[0], truth, 0.01, 2);
  const RefineScan scan{0, ranges, Pose()};
  MclConfig cfg;
  const Pose start = Pose::planar(truth.x() + 0.08, truth.y() + 0.05, truth.yaw() - deg2rad(1.5));
  const RefineResult res = refinePose(caster, rig, std::span(&scan, 1), start, 3, cfg.refine);
  ASSERT_TRUE(res.accepted) << res.reason;
  EXPECT_LT(posErr(res.pose, truth), 0.025);
  EXPECT_LT(yawErrDeg(res.pose, truth), 0.5);
}

TEST(RobotClearance, InscribedRadiusOfFootprints) {
  RobotSpec round;
  round.radius = 0.3;
  EXPECT_DOUBLE_EQ(round.inscribedRadius(), 0.3);
  RobotSpec box;
  box.footprint = {{0.3, 0.25}, {-0.3, 0.25}, {-0.3, -0.25}, {0.3, -0.25}};
  EXPECT_NEAR(box.inscribedRadius(), 0.25, 1e-12);
  RobotSpec ahead;  // base_link at the back edge: the outline touches it
  ahead.footprint = {{0.6, 0.25}, {0, 0.25}, {0, -0.25}, {0.6, -0.25}};
  EXPECT_NEAR(ahead.inscribedRadius(), 0.0, 1e-12);
  RobotSpec outside;  // base_link outside the body
  outside.footprint = {{0.8, 0.25}, {0.2, 0.25}, {0.2, -0.25}, {0.8, -0.25}};
  EXPECT_DOUBLE_EQ(outside.inscribedRadius(), 0.0);
}

TEST(RobotClearance, ComesFromTheRobotSectionNotASecondSize) {
  TempDir dir;
  const std::string map = dir.write("map.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string cfg = dir.write("c.yaml", "map: map.obj\nrobot: {footprint: [[0.35, 0.3], [-0.35, 0.3], [-0.35, -0.3], [0.35, -0.3]]}\n"
                                              "rig: taser\nmcl: {clearance_margin: 0.1}\n");
  EXPECT_NEAR(loadConfig(cfg).mcl.clearance, 0.3 - 0.1, 1e-12);
  const std::string round = dir.write("r.yaml", "map: map.obj\nrobot: {radius: 0.25}\nrig: taser\n");
  EXPECT_NEAR(loadConfig(round).mcl.clearance, 0.25 - MclConfig{}.clearance_margin, 1e-12);
  const std::string old = dir.write("o.yaml", "map: map.obj\nrobot: {radius: 0.25}\nrig: taser\nmcl:\n  robot_radius: 0.25\n");
  try {
    loadConfig(old);
    FAIL() << "mcl.robot_radius accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("o.yaml:5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("robot.radius or robot.footprint"), std::string::npos) << e.what();
  }
}

TEST(RecordedRigConfig, OnlyCommandsThatReadARecordingTakeIt) {
  TempDir dir;
  dir.write("map.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string cfg = dir.write("c.yaml", "map: map.obj\nrobot: {radius: 0.25}\nrig: recorded\n");
  const PolylocConfig c = loadConfig(cfg, {.recorded_rig = true});
  EXPECT_TRUE(c.rig_from_recording);
  EXPECT_EQ(c.rig.size(), 0u);
  try {
    loadConfig(cfg);
    FAIL() << "a recorded rig accepted where no recording is";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("c.yaml:3"), std::string::npos) << e.what();
  }
  const std::string none = dir.write("n.yaml", "robot: {radius: 0.25}\n");  // no map, no rig
  EXPECT_TRUE(loadConfig(none, {.map_optional = true, .recorded_rig = true}).rig_from_recording);
  EXPECT_THROW(loadConfig(none), ConfigError);
}

}  // namespace
}  // namespace polyloc::test
