// polynav's controller tools with known answers: following an L-shaped path (distance, progress
// that never goes backwards, the carrot round the corner, the turn ahead, what remains), the scan
// tools (scan points in the map frame at a pose with yaw, polygons as virtual obstacles that
// shorten only the beams meeting them, free travel of the hull forward and backward, the corner
// circle of a turn in place, the first obstruction along a path) and the map_server grid reader
// (cells bottom-up, unknown as occupied, the danger mask, errors that name the file and the key).
#include <polynav/grid_io.hpp>
#include <polynav/hull.hpp>
#include <polynav/path_follow.hpp>
#include <polynav/polar_scan.hpp>
#include <polynav/scan_tools.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_nav_follow {

using namespace polynav;
using Eigen::Vector2d;
using Eigen::Vector3d;


constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = M_PI / 180;

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The L of the tests: 4 m along +x, then 4 m along +y.
PathFollow lPath() { return PathFollow({{0, 0}, {4, 0}, {4, 4}}); }

// A full-turn scan of 1-degree beams from -pi (beam 180 straight ahead, 270 to the left), nothing
// seen (range_max + 1) everywhere.
PolarScan emptyScan(double range_max = 5.0) {
  PolarScan s;
  s.angle_min = -M_PI, s.angle_increment = 1 * kDeg, s.range_max = range_max;
  s.ranges.assign(360, float(range_max + 1));
  return s;
}

// Beam index of the 1-degree scan along `deg` (-180 <= deg < 180).
size_t beam(int deg) { return size_t(deg + 180); }


// ------------------------------------------------------------------------------------ PathFollow

TEST(NavPathFollow, DistanceAndProgressBesideTheFirstLeg) {
  PathFollow f = lPath();
  ASSERT_FALSE(f.empty());
  EXPECT_DOUBLE_EQ(f.remaining(), 8.0);
  EXPECT_NEAR(f.update({2.0, 0.5}), 0.5, 1e-12);
  EXPECT_NEAR(f.travelled(), 2.0, 1e-12);
  EXPECT_EQ(f.segment(), 0u);
  EXPECT_NEAR(f.remaining(), 6.0, 1e-12);
  // A point beside the path behind the progress: the progress stays, the distance is to it.
  EXPECT_NEAR(f.update({1.0, 0.3}), std::hypot(1.0, 0.3), 1e-12);
  EXPECT_NEAR(f.travelled(), 2.0, 1e-12);
  // Right of the leg (negative y) counts the same.
  EXPECT_NEAR(f.update({3.0, -0.4}), 0.4, 1e-12);
  EXPECT_NEAR(f.travelled(), 3.0, 1e-12);
  EXPECT_NEAR(f.update({0.0, 0.0}), 3.0, 1e-12);  // the start again: never backwards
  EXPECT_NEAR(f.travelled(), 3.0, 1e-12);
}

TEST(NavPathFollow, SearchWindowAndSecondLeg) {
  // Near the second leg but beyond the 2 m window: only the first leg is searched.
  PathFollow f = lPath();
  EXPECT_NEAR(f.update({4.3, 3.0}), std::hypot(0.3, 3.0), 1e-12);
  EXPECT_NEAR(f.travelled(), 4.0, 1e-12);
  // From the corner the second leg lies within the window.
  EXPECT_NEAR(f.update({4.3, 3.0}), 0.3, 1e-12);
  EXPECT_EQ(f.segment(), 1u);
  EXPECT_NEAR(f.travelled(), 7.0, 1e-12);
  EXPECT_NEAR(f.remaining(), 1.0, 1e-12);
  // A wide window finds it at once.
  PathFollow g = lPath();
  EXPECT_NEAR(g.update({4.3, 3.0}, 10.0), 0.3, 1e-12);
  EXPECT_NEAR(g.travelled(), 7.0, 1e-12);
  // Past the end: the end, nothing remains, the carrot stays there.
  EXPECT_NEAR(g.update({4.0, 5.0}), 1.0, 1e-12);
  EXPECT_NEAR(g.remaining(), 0.0, 1e-12);
  EXPECT_TRUE(g.carrot(1.0).isApprox(Vector2d(4, 4)));
}

TEST(NavPathFollow, CarrotRoundTheCorner) {
  PathFollow f = lPath();
  EXPECT_NEAR(f.update({3.5, 0.0}), 0.0, 1e-12);
  const Vector2d c = f.carrot(1.0);
  EXPECT_NEAR(c.x(), 4.0, 1e-12);
  EXPECT_NEAR(c.y(), 0.5, 1e-12);
  EXPECT_TRUE(f.carrot(0.0).isApprox(Vector2d(3.5, 0)));
  EXPECT_TRUE(f.carrot(0.5).isApprox(Vector2d(4, 0)));
  EXPECT_TRUE(f.carrot(100).isApprox(Vector2d(4, 4)));
  EXPECT_NEAR(f.remaining(), 4.5, 1e-12);
  // Direction: along x here, along y past the corner.
  EXPECT_TRUE(f.direction(0).isApprox(Vector2d(1, 0)));
  EXPECT_TRUE(f.direction(1.0).isApprox(Vector2d(0, 1)));
}

TEST(NavPathFollow, TurnAhead) {
  PathFollow f = lPath();
  f.update({3.5, 0.0});
  EXPECT_NEAR(f.turnAhead(1.0), M_PI / 2, 1e-9);
  EXPECT_NEAR(f.turnAhead(0.3), 0.0, 1e-9);  // the corner is 0.5 m on: not within 0.3 m
  PathFollow g = lPath();
  g.update({1.0, 0.0});
  EXPECT_NEAR(g.turnAhead(1.0), 0.0, 1e-12);
  EXPECT_NEAR(g.remaining(), 7.0, 1e-12);
  // A path that turns left then right: the largest change, not the sum or the last.
  PathFollow z({{0, 0}, {1, 0}, {1, 1}, {2, 1}});
  EXPECT_NEAR(z.turnAhead(3.0), M_PI / 2, 1e-9);
}

TEST(NavPathFollow, EmptyAndSinglePoint) {
  PathFollow none;
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.update({1, 1}), kInf);
  EXPECT_DOUBLE_EQ(none.remaining(), 0.0);
  EXPECT_DOUBLE_EQ(none.turnAhead(1.0), 0.0);
  PathFollow one({{1, 2}});
  EXPECT_TRUE(one.empty());
  EXPECT_NEAR(one.update({4, 6}), 5.0, 1e-12);
}

// ------------------------------------------------------------------------------------ scan tools

TEST(NavScanTools, ScanPointsAtAPoseWithYaw) {
  PolarScan s;
  s.angle_min = -M_PI, s.angle_increment = M_PI / 2, s.range_max = 5.0;
  // Beams at -180, -90, 0, 90 degrees: nothing, 2 m, 1 m, no reading (0).
  s.ranges = {6.0f, 2.0f, 1.0f, 0.0f};
  const Vector3d pose(1, 2, M_PI / 2);  // facing +y
  const std::vector<Vector2d> p = scanPoints(s, pose);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0].x(), 3.0, 1e-6);  // 2 m to the robot's right: +x in the map
  EXPECT_NEAR(p[0].y(), 2.0, 1e-6);
  EXPECT_NEAR(p[1].x(), 1.0, 1e-6);  // 1 m ahead: +y in the map
  EXPECT_NEAR(p[1].y(), 3.0, 1e-6);
  // NaN, +inf and exactly range_max: the first two skipped, range_max seen.
  s.ranges = {std::numeric_limits<float>::quiet_NaN(), float(kInf), 5.0f, 0.0f};
  const std::vector<Vector2d> q = scanPoints(s, {0, 0, 0});
  ASSERT_EQ(q.size(), 1u);
  EXPECT_NEAR(q[0].x(), 5.0, 1e-6);
  EXPECT_NEAR(q[0].y(), 0.0, 1e-6);
}

TEST(NavScanTools, AddPolygonsShortensBeamsToTheEdge) {
  // A 1 m square 2 m ahead of the robot (map frame), robot at the origin facing +x.
  const Polygon square = {{2, -0.5}, {3, -0.5}, {3, 0.5}, {2, 0.5}};
  PolarScan s = emptyScan();
  s.ranges[beam(-90)] = 1.5f;  // a real return elsewhere stays
  s.ranges[beam(5)] = 1.0f;    // a real return nearer than the square stays too
  addPolygons(s, {square}, {0, 0, 0});
  EXPECT_NEAR(s.ranges[beam(0)], 2.0, 1e-6);
  EXPECT_NEAR(s.ranges[beam(10)], 2.0 / std::cos(10 * kDeg), 1e-5);  // 2 tan(10 deg) = 0.35 < 0.5: the near face
  EXPECT_NEAR(s.ranges[beam(-10)], 2.0 / std::cos(10 * kDeg), 1e-5);
  EXPECT_NEAR(s.ranges[beam(5)], 1.0, 1e-6);
  EXPECT_NEAR(s.ranges[beam(-90)], 1.5, 1e-6);
  // Beams that miss the square are unchanged: 20 degrees passes beside it (2 tan 20 = 0.73 > 0.5).
  for (int deg : {20, -20, 45, 90, 179, -180, -135})
    EXPECT_EQ(s.ranges[beam(deg)], 6.0f) << deg << " deg";
  // The same square seen from a pose with yaw: robot at (2.5, -2) facing +y, the square 1.5 m ahead.
  PolarScan r = emptyScan();
  addPolygons(r, {square}, {2.5, -2, M_PI / 2});
  EXPECT_NEAR(r.ranges[beam(0)], 1.5, 1e-6);
  EXPECT_EQ(r.ranges[beam(-90)], 6.0f);  // to the robot's right: +x in the map, nothing
  EXPECT_EQ(r.ranges[beam(90)], 6.0f);
}

TEST(NavScanTools, FreeTravelAheadBesideAndBackward) {
  const RectHull hull;  // 0.6 x 0.5: front = rear = 0.3, left = right = 0.25
  PolarScan s = emptyScan();
  EXPECT_EQ(freeTravel(s, hull, true), kInf);  // nothing seen
  // A point ahead inside the hull band: 1.2 m along 5 degrees (y = 0.105 < 0.25).
  s.ranges[beam(5)] = 1.2f;
  const double x5 = double(1.2f) * std::cos(5 * kDeg);
  EXPECT_NEAR(freeTravel(s, hull, true), x5 - 0.3, 1e-6);
  // A nearer point beside the hull (0.7 m along 40 degrees: y = 0.45 > 0.25) does not count.
  s.ranges[beam(40)] = 0.7f;
  EXPECT_NEAR(freeTravel(s, hull, true), x5 - 0.3, 1e-6);
  // A nearer point straight ahead does.
  s.ranges[beam(0)] = 0.9f;
  EXPECT_NEAR(freeTravel(s, hull, true), 0.6, 1e-6);
  // Backward: only points behind count; 0.8 m along -175 degrees (x = -0.797, y = -0.07).
  EXPECT_EQ(freeTravel(s, hull, false), kInf);
  s.ranges[beam(-175)] = 0.8f;
  EXPECT_NEAR(freeTravel(s, hull, false), double(0.8f) * std::cos(5 * kDeg) - 0.3, 1e-6);
  EXPECT_NEAR(freeTravel(s, hull, true), 0.6, 1e-6);  // ahead unchanged
  // A point inside the hull: no room at all (never negative).
  s.ranges[beam(0)] = 0.2f;
  EXPECT_EQ(freeTravel(s, hull, true), 0.0);
}

TEST(NavScanTools, RotationClearCornerCircle) {
  const RectHull hull;  // corner radius hypot(0.3, 0.25) = 0.39
  PolarScan s = emptyScan();
  EXPECT_TRUE(rotationClear(s, hull, M_PI));
  // 0.05 m beyond the left side: clear standing still, not when turning either way (the corners
  // sweep a circle of 0.39 m).
  s.ranges[beam(90)] = 0.30f;
  EXPECT_TRUE(rotationClear(s, hull, 0.0));
  EXPECT_FALSE(rotationClear(s, hull, 0.5));
  EXPECT_FALSE(rotationClear(s, hull, -0.5));
  // The margin: 0.03 m beyond the side with the default 0.02 clear at rest, not with 0.05.
  PolarScan m = emptyScan();
  m.ranges[beam(90)] = 0.28f;
  EXPECT_TRUE(rotationClear(m, hull, 0.0));
  EXPECT_FALSE(rotationClear(m, hull, 0.0, 0.05));
  // Farther than the corner radius (+ margin): clear for any turn.
  PolarScan far = emptyScan();
  for (int deg = -180; deg < 180; deg += 15) far.ranges[beam(deg)] = 0.42f;
  EXPECT_TRUE(rotationClear(far, hull, 2 * M_PI));
  EXPECT_TRUE(rotationClear(far, hull, -1.0));
  // A small turn keeps the side's point clear, a larger one does not.
  EXPECT_TRUE(rotationClear(s, hull, 0.05));
  // 0.06 m ahead of the front: a turn of 0.1 rad clears it, one of 0.5 rad swings the front
  // corner into it (the hull reaches 0.3 / cos(0.5) = 0.34 m along the point's direction).
  PolarScan ahead = emptyScan();
  ahead.ranges[beam(0)] = 0.36f;
  EXPECT_TRUE(rotationClear(ahead, hull, 0.1));
  EXPECT_TRUE(rotationClear(ahead, hull, -0.1));
  EXPECT_FALSE(rotationClear(ahead, hull, 0.5));
  EXPECT_FALSE(rotationClear(ahead, hull, -0.5));
}

TEST(NavScanTools, ObstructedAtFirstPointWithinRadius) {
  const std::vector<Vector2d> path = {{0, 0}, {4, 0}, {4, 4}};
  Vector2d where(-1, -1);
  // Nothing near: -1 (and `where` untouched).
  EXPECT_LT(obstructedAt({{2, 1}, {5, 2}}, path, 0, 10, 0.3, &where), 0);
  EXPECT_EQ(where, Vector2d(-1, -1));
  // On the first leg: arc length 2.
  EXPECT_NEAR(obstructedAt({{2, 0.2}}, path, 0, 10, 0.3, &where), 2.0, 1e-12);
  EXPECT_EQ(where, Vector2d(2, 0.2));
  // On the second leg 1 m up: arc length 5 from the start, 1 from segment 1.
  EXPECT_NEAR(obstructedAt({{4.2, 1.0}}, path, 0, 10, 0.3, &where), 5.0, 1e-12);
  EXPECT_EQ(where, Vector2d(4.2, 1.0));
  EXPECT_NEAR(obstructedAt({{4.2, 1.0}}, path, 1, 10, 0.3), 1.0, 1e-12);
  // The first along the path, whatever the order of the points.
  EXPECT_NEAR(obstructedAt({{4.2, 1.0}, {3.0, -0.1}}, path, 0, 10, 0.3, &where), 3.0, 1e-12);
  EXPECT_EQ(where, Vector2d(3.0, -0.1));
  // Beyond ahead_m: the second leg starts at 4 m, not looked at within 3 m.
  EXPECT_LT(obstructedAt({{4.2, 1.0}}, path, 0, 3.0, 0.3), 0);
  // The radius is strict: a point 0.3 m off is not within 0.3 m.
  EXPECT_LT(obstructedAt({{2, 0.3}}, path, 0, 10, 0.3), 0);
  EXPECT_NEAR(obstructedAt({{2, 0.3}}, path, 0, 10, 0.31), 2.0, 1e-12);
  // Past the last segment: nothing to check.
  EXPECT_LT(obstructedAt({{4, 4}}, path, 2, 10, 0.3), 0);
}

// --------------------------------------------------------------------------------------- grid io


// A binary PGM (P5) of `rows` (row 0 = the image's top).
std::string pgm(const std::vector<std::vector<uint8_t>>& rows) {
  std::string out = "P5\n" + std::to_string(rows[0].size()) + " " + std::to_string(rows.size()) + "\n255\n";
  for (const auto& r : rows) out.append(r.begin(), r.end());
  return out;
}

constexpr uint8_t F = 254, O = 0, U = 205;  // map_server: free, occupied, unknown

// 4 x 3: top row all free but its last (occupied), middle row unknown in its first cell, bottom
// row occupied in its first cell.
const std::vector<std::vector<uint8_t>> kImage = {{F, F, F, O}, {U, F, F, F}, {O, F, F, F}};

std::string yaml(const std::string& image, const std::string& extra = "", const std::string& origin = "[1.0, 2.0, 0.0]",
                 const std::string& resolution = "resolution: 0.05\n") {
  return "image: " + image + "\n" + resolution + "origin: " + origin +
         "\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n" + extra;
}

std::string loadError(const std::string& path) {
  try {
    loadNavGrid(path);
  } catch (const GridIoError& e) {
    return e.what();
  }
  return "(nothing thrown)";
}


TEST(NavGridIo, CellsBottomUpUnknownIsOccupied) {
  polyloc::test::TempDir dir;
  dir.write("map.pgm", pgm(kImage));
  const std::string y = dir.write("map.yaml", yaml("map.pgm"));
  const LoadedGrid lg = loadNavGrid(y);
  const NavGrid& g = lg.grid;
  EXPECT_EQ(g.width, 4u);
  EXPECT_EQ(g.height, 3u);
  EXPECT_DOUBLE_EQ(g.resolution, 0.05);
  EXPECT_DOUBLE_EQ(g.origin_x, 1.0);
  EXPECT_DOUBLE_EQ(g.origin_y, 2.0);
  EXPECT_TRUE(lg.danger.empty());
  EXPECT_TRUE(g.door.empty());
  // Cell row 0 is the image's last row.
  const std::vector<std::vector<uint8_t>> expect = {{1, 0, 0, 0},   // iy 0 = image row 2
                                                    {1, 0, 0, 0},   // iy 1 = image row 1 (unknown first)
                                                    {0, 0, 0, 1}};  // iy 2 = image row 0
  for (size_t iy = 0; iy < 3; ++iy)
    for (size_t ix = 0; ix < 4; ++ix) EXPECT_EQ(g.occupied[g.index(ix, iy)], expect[iy][ix]) << ix << "," << iy;
  // World positions: the origin is cell (0, 0)'s outer corner.
  EXPECT_EQ(g.cellAt({1.01, 2.01}), g.index(0, 0));
  EXPECT_EQ(g.cellAt({1.19, 2.14}), g.index(3, 2));
  EXPECT_EQ(g.cellAt({0.99, 2.01}), std::nullopt);
}

TEST(NavGridIo, NegateFlipsTheImage) {
  polyloc::test::TempDir dir;
  dir.write("map.pgm", pgm({{0, 255}}));  // negate: black = free, white = occupied
  const LoadedGrid lg = loadNavGrid(dir.write("map.yaml", "image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 1\n"));
  ASSERT_EQ(lg.grid.size(), 2u);
  EXPECT_EQ(lg.grid.occupied[0], 0);
  EXPECT_EQ(lg.grid.occupied[1], 1);
}

TEST(NavGridIo, DangerMaskBeside) {
  polyloc::test::TempDir dir;
  dir.write("map.pgm", pgm(kImage));
  // Danger (0) in the image's top-left and bottom-right cells.
  dir.write("map.danger.pgm", pgm({{0, 255, 255, 255}, {255, 255, 255, 255}, {255, 255, 255, 0}}));
  const LoadedGrid lg = loadNavGrid(dir.write("map.yaml", yaml("map.pgm")));
  ASSERT_EQ(lg.danger.size(), 12u);
  const NavGrid& g = lg.grid;
  size_t n = 0;
  for (uint8_t d : lg.danger) n += d;
  EXPECT_EQ(n, 2u);
  EXPECT_EQ(lg.danger[g.index(0, 2)], 1);  // top-left of the image: the top cell row
  EXPECT_EQ(lg.danger[g.index(3, 0)], 1);  // bottom-right: cell row 0
  EXPECT_EQ(lg.danger[g.index(0, 0)], 0);
  // The occupancy is the map's, not the mask's.
  EXPECT_EQ(g.occupied[g.index(3, 0)], 0);
}

TEST(NavGridIo, ErrorsNameTheFileAndTheKey) {
  polyloc::test::TempDir dir;
  dir.write("map.pgm", pgm(kImage));
  // No such yaml.
  const std::string missing = dir.file("nope.yaml");
  std::string e = loadError(missing);
  EXPECT_TRUE(has(e, missing)) << e;
  EXPECT_TRUE(has(e, "no such file")) << e;
  // Missing key 'resolution'.
  std::string y = dir.write("nores.yaml", yaml("map.pgm", "", "[1.0, 2.0, 0.0]", ""));
  e = loadError(y);
  EXPECT_TRUE(has(e, y)) << e;
  EXPECT_TRUE(has(e, "missing key 'resolution'")) << e;
  // Missing key 'image'.
  y = dir.write("noimage.yaml", "resolution: 0.05\norigin: [0, 0, 0]\n");
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "missing key 'image'")) << e;
  // Resolution <= 0.
  y = dir.write("zerores.yaml", yaml("map.pgm", "", "[1.0, 2.0, 0.0]", "resolution: 0\n"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "resolution")) << e;
  // A rotated origin.
  y = dir.write("rotated.yaml", yaml("map.pgm", "", "[1.0, 2.0, 0.1]"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y)) << e;
  EXPECT_TRUE(has(e, "origin yaw")) << e;
  EXPECT_TRUE(has(e, "rotated")) << e;
  // An origin that is not [x, y, yaw].
  y = dir.write("short.yaml", yaml("map.pgm", "", "[1.0, 2.0]"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "origin")) << e;
  // A key given twice: yaml-cpp kept one of them silently.
  y = dir.write("twice.yaml", yaml("map.pgm", "resolution: 0.1\n"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "line 7: key 'resolution' given twice")) << e;
  // A key of the wrong type.
  y = dir.write("badtype.yaml", yaml("map.pgm", "", "[1.0, 2.0, 0.0]", "resolution: fine\n"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "wrong type")) << e;
  // The image it names does not exist / does not decode.
  y = dir.write("noimg.yaml", yaml("gone.pgm"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "gone.pgm") && has(e, "does not exist")) << e;
  dir.write("junk.pgm", "this is not an image");
  y = dir.write("junk.yaml", yaml("junk.pgm"));
  e = loadError(y);
  EXPECT_TRUE(has(e, y) && has(e, "junk.pgm") && has(e, "could not be decoded")) << e;
  // A danger mask of another size: the error names the mask and both sizes.
  polyloc::test::TempDir other;
  other.write("map.pgm", pgm(kImage));
  const std::string mask = other.write("map.danger.pgm", pgm({{0, 255, 255}, {255, 255, 255}}));
  e = loadError(other.write("map.yaml", yaml("map.pgm")));
  EXPECT_TRUE(has(e, mask)) << e;
  EXPECT_TRUE(has(e, "3x2")) << e;
  EXPECT_TRUE(has(e, "4x3")) << e;
}

}  // namespace polyloc::t_nav_follow
