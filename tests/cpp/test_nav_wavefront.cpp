// polynav's global planner: the wavefront over an inflated grid with known answers (straight
// runs, diagonals, a corridor corner, door gaps for a 0.6 m robot), blocked cells that age out
// (never door cells), the look-ahead check, determinism and errors that name the field.
#include <polynav/nav_grid.hpp>
#include <polynav/wavefront.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_nav_wavefront {

using namespace polynav;
using Eigen::Vector2d;


NavGrid grid(size_t w, size_t h, uint8_t value = 0) {
  NavGrid g;
  g.width = w, g.height = h, g.resolution = 0.05;
  g.occupied.assign(w * h, value);
  return g;
}

// Cells [x0, x1) x [y0, y1) set to `v`.
void fill(std::vector<uint8_t>& cells, const NavGrid& g, size_t x0, size_t y0, size_t x1, size_t y1, uint8_t v) {
  for (size_t y = y0; y < y1; ++y)
    for (size_t x = x0; x < x1; ++x) cells[g.index(x, y)] = v;
}

// A 6 x (h / 20) m room with a wall two cells thick at x = 3 m and gaps [y0, y1) (in cells).
NavGrid wall(size_t h, std::vector<std::pair<size_t, size_t>> gaps) {
  NavGrid g = grid(120, h);
  fill(g.occupied, g, 60, 0, 62, h, 1);
  for (auto [y0, y1] : gaps) fill(g.occupied, g, 60, y0, 62, y1, 0);
  return g;
}

std::vector<size_t> cells(const NavGrid& g, size_t x0, size_t y0, size_t x1, size_t y1) {
  std::vector<size_t> out;
  for (size_t y = y0; y < y1; ++y)
    for (size_t x = x0; x < x1; ++x) out.push_back(g.index(x, y));
  return out;
}

std::string thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}


TEST(NavWavefront, EmptyGridStraightRun) {
  const NavGrid g = grid(200, 80);  // 10 x 4 m
  Wavefront w;
  const WavefrontPlan p = w.plan(g, {}, {1, 2}, {9, 2});
  ASSERT_TRUE(p.reachable) << p.why;
  EXPECT_NEAR(p.length_m, 8.0, 0.05);
  for (const Vector2d& q : p.path) EXPECT_NEAR(q.y(), 2.0, 0.05);  // one row: straight
  EXPECT_EQ(p.path.back(), Vector2d(9, 2));
  EXPECT_EQ(p.path.front(), g.centre(*g.cellAt({1, 2})));
  ASSERT_EQ(w.costs().size(), g.size());
  EXPECT_EQ(w.costs()[*g.cellAt({9, 2})], 0.0);
  EXPECT_NEAR(w.costs()[*g.cellAt({1, 2})], 8.0, 0.05);
}

TEST(NavWavefront, DiagonalFourVersusEightConnected) {
  const NavGrid g = grid(200, 80);
  const Vector2d a = g.centre(20, 20), b = g.centre(60, 60);  // 2 m along x and y, on cell centres
  WavefrontConfig four;
  four.eight_connected = false;
  const WavefrontPlan p8 = Wavefront().plan(g, {}, a, b), p4 = Wavefront(four).plan(g, {}, a, b);
  ASSERT_TRUE(p8.reachable && p4.reachable);
  EXPECT_NEAR(p8.length_m, 40 * std::sqrt(2.0) * 0.05, 1e-9);
  EXPECT_NEAR(p4.length_m, 4.0, 1e-9);
  EXPECT_EQ(p8.path.size(), 41u);
  EXPECT_EQ(p4.path.size(), 81u);
}

TEST(NavWavefront, DiagonalsDoNotCutCorners) {
  NavGrid g = grid(2, 2);
  g.occupied[g.index(1, 0)] = 1;
  const WavefrontPlan p = Wavefront().plan(g, {}, g.centre(0, 0), g.centre(1, 1));
  ASSERT_TRUE(p.reachable);
  EXPECT_NEAR(p.length_m, 0.1, 1e-12);  // round by (0, 1), not 0.0707 across the corner
  g.occupied[g.index(0, 1)] = 1;
  EXPECT_EQ(Wavefront().plan(g, {}, g.centre(0, 0), g.centre(1, 1)).why, "goal unreachable from the start");
}

TEST(NavWavefront, LShapedCorridorGoesRoundTheCorner) {
  NavGrid g = grid(200, 200, 1);               // 10 x 10 m, all occupied but
  fill(g.occupied, g, 20, 20, 180, 40, 0);     // x 1..9, y 1..2
  fill(g.occupied, g, 160, 20, 180, 180, 0);   // x 8..9, y 1..9
  const Vector2d start = g.centre(20, 39), goal = g.centre(160, 179);  // along the inner walls
  const WavefrontPlan p = Wavefront().plan(g, {}, start, goal);
  ASSERT_TRUE(p.reachable) << p.why;
  // The polyline (1.025, 1.975) -> (8.025, 1.975) -> (8.025, 8.975): 7 + 7 m.
  EXPECT_NEAR(p.length_m, 14.0, 2 * g.resolution);
  bool corner = false;
  for (const Vector2d& q : p.path) {
    EXPECT_FALSE(g.occupied[*g.cellAt(q)]) << q.transpose();
    corner = corner || (q.x() > 8 && q.y() < 2);
  }
  EXPECT_TRUE(corner);
}

TEST(NavWavefront, RobotOf0_6mPassesA0_75mDoorNotA0_5mGap) {
  const NavGrid door = inflate(wall(80, {{33, 48}}), 0.3);  // 15 cells, centred on y = 2.025
  const WavefrontPlan p = Wavefront().plan(door, {}, {1, 2}, {5, 2});
  ASSERT_TRUE(p.reachable) << p.why;
  EXPECT_NEAR(p.length_m, 4.0, 2 * door.resolution);
  const NavGrid narrow = inflate(wall(80, {{35, 45}}), 0.3);  // 10 cells
  const WavefrontPlan q = Wavefront().plan(narrow, {}, {1, 2}, {5, 2});
  EXPECT_FALSE(q.reachable);
  EXPECT_EQ(q.why, "goal unreachable from the start");
  EXPECT_TRUE(q.path.empty());
}

TEST(NavWavefront, BlockedGapIsClosedUntilItAges) {
  const NavGrid g = inflate(wall(80, {{33, 48}}), 0.3);
  Wavefront w;
  const WavefrontPlan open = w.plan(g, {}, {1, 2}, {5, 2});
  ASSERT_TRUE(open.reachable);
  BlockedCells b;
  EXPECT_TRUE(b.block(g, cells(g, 60, 33, 62, 48), 100.0).empty());
  EXPECT_EQ(b.size(), 30u);
  EXPECT_EQ(w.plan(g, b, {1, 2}, {5, 2}).why, "goal unreachable from the start");
  b.age(129.9, w.config().blocked_max_age_s);
  EXPECT_EQ(b.size(), 30u);
  b.age(130.0, w.config().blocked_max_age_s);
  EXPECT_EQ(b.size(), 0u);
  const WavefrontPlan again = w.plan(g, b, {1, 2}, {5, 2});
  ASSERT_TRUE(again.reachable);
  EXPECT_EQ(again.path, open.path);
}

TEST(NavWavefront, BlockedGapForcesTheDetour) {
  const NavGrid g = inflate(wall(120, {{33, 48}, {93, 108}}), 0.3);  // gaps at y = 2 and 5 m
  Wavefront w;
  const WavefrontPlan near = w.plan(g, {}, {1, 2}, {5, 2});
  ASSERT_TRUE(near.reachable);
  BlockedCells b;
  b.block(g, cells(g, 60, 33, 62, 48), 0.0);
  const WavefrontPlan detour = w.plan(g, b, {1, 2}, {5, 2});
  ASSERT_TRUE(detour.reachable) << detour.why;
  EXPECT_GT(detour.length_m, near.length_m + 3.0);  // up 3 m and back down
  double top = 0;
  for (const Vector2d& q : detour.path) top = std::max(top, q.y());
  EXPECT_GT(top, 4.8);
  b.age(30.0, 30.0);
  EXPECT_EQ(w.plan(g, b, {1, 2}, {5, 2}).path, near.path);
}

TEST(NavWavefront, DoorCellsAreReportedNotBlocked) {
  NavGrid g = inflate(wall(80, {{33, 48}}), 0.3);
  g.door.assign(g.size(), 0);
  fill(g.door, g, 60, 33, 62, 48, 1);
  std::vector<size_t> found = cells(g, 60, 33, 62, 48);
  found.push_back(g.index(10, 10));
  BlockedCells b;
  const std::vector<size_t> doors = b.block(g, found, 5.0);
  EXPECT_EQ(doors, cells(g, 60, 33, 62, 48));
  EXPECT_EQ(b.size(), 1u);
  EXPECT_TRUE(b.blocked(g.index(10, 10)));
  EXPECT_FALSE(b.blocked(g.index(60, 40)));
  EXPECT_TRUE(Wavefront().plan(g, b, {1, 2}, {5, 2}).reachable);
}

TEST(NavWavefront, StartAndGoalReasons) {
  const NavGrid g = wall(80, {{33, 48}});
  Wavefront w;
  EXPECT_EQ(w.plan(g, {}, {-0.1, 2}, {5, 2}).why, "start outside the grid");
  EXPECT_EQ(w.plan(g, {}, {3.01, 1}, {5, 2}).why, "start in an obstacle");
  EXPECT_EQ(w.plan(g, {}, {1, 2}, {5, 4.0}).why, "goal outside the grid");
  EXPECT_EQ(w.plan(g, {}, {1, 2}, {3.06, 3}).why, "goal in an obstacle");
  BlockedCells b;
  b.block(g, {*g.cellAt({5, 2})}, 0.0);
  EXPECT_EQ(w.plan(g, b, {1, 2}, {5, 2}).why, "goal in a blocked cell");
  b.clear();
  b.block(g, {*g.cellAt({1, 2})}, 0.0);  // the robot stands there: its own cell stays passable
  EXPECT_TRUE(w.plan(g, b, {1, 2}, {5, 2}).reachable);
  const WavefrontPlan p = w.plan(g, {}, {1, 2}, {-1, 2});
  EXPECT_FALSE(p.reachable);
  EXPECT_EQ(p.length_m, 0.0);
  for (double c : w.costs()) EXPECT_TRUE(std::isinf(c));
}

TEST(NavWavefront, PathBlockedLooksAhead) {
  const NavGrid g = grid(200, 80);
  const WavefrontPlan p = Wavefront().plan(g, {}, {1, 2}, {9, 2});
  ASSERT_TRUE(p.reachable);
  BlockedCells one_m, three_m;
  one_m.block(g, {*g.cellAt({2.03, 2.0})}, 0.0);    // 1 m past the start cell's centre
  three_m.block(g, {*g.cellAt({4.03, 2.0})}, 0.0);  // 3 m
  EXPECT_TRUE(pathBlocked(g, one_m, p.path, 0, 2.0));
  EXPECT_FALSE(pathBlocked(g, three_m, p.path, 0, 2.0));
  EXPECT_TRUE(pathBlocked(g, three_m, p.path, 0, 3.5));
  EXPECT_FALSE(pathBlocked(g, one_m, p.path, 30, 2.0));  // already past it
  EXPECT_FALSE(pathBlocked(g, one_m, p.path, p.path.size(), 2.0));
  NavGrid wall_ahead = g;
  wall_ahead.occupied[*g.cellAt({2.5, 2.0})] = 1;  // the map changed under the path
  EXPECT_TRUE(pathBlocked(wall_ahead, {}, p.path, 0, 2.0));
}

TEST(NavWavefront, SameInputSamePath) {
  const NavGrid g = inflate(wall(120, {{33, 48}, {93, 108}}), 0.3);
  WavefrontConfig c;
  c.eight_connected = false;  // many equal staircases: the tie rule picks one
  c.clearance_weight = 1.0;
  Wavefront a(c), b(c);
  const WavefrontPlan pa = a.plan(g, {}, {0.5, 0.5}, {5.5, 5.5}), pb = b.plan(g, {}, {0.5, 0.5}, {5.5, 5.5});
  ASSERT_TRUE(pa.reachable);
  EXPECT_EQ(pa.path, pb.path);
  EXPECT_EQ(pa.length_m, pb.length_m);
  EXPECT_EQ(a.costs(), b.costs());
  EXPECT_EQ(a.plan(g, {}, {0.5, 0.5}, {5.5, 5.5}).path, pa.path);
}

TEST(NavWavefront, ClearanceCostKeepsAwayFromAWall) {
  NavGrid g = grid(200, 40);              // 10 x 2 m
  fill(g.occupied, g, 0, 0, 200, 1, 1);  // a wall along the bottom
  WavefrontConfig c;
  c.clearance_weight = 2.0, c.clearance_range = 1.0;
  const WavefrontPlan shortest = Wavefront().plan(g, {}, {1, 0.3}, {9, 0.3});
  const WavefrontPlan clear = Wavefront(c).plan(g, {}, {1, 0.3}, {9, 0.3});
  ASSERT_TRUE(shortest.reachable && clear.reachable);
  double top = 0;
  for (const Vector2d& q : clear.path) top = std::max(top, q.y());
  EXPECT_NEAR(shortest.length_m, 8.0, 0.05);
  EXPECT_GT(top, 0.6);
  EXPECT_GT(clear.length_m, shortest.length_m);
}

TEST(NavWavefront, InflateMatchesHandComputedDisc) {
  NavGrid g = grid(21, 21);
  g.occupied[g.index(10, 10)] = 1;
  g.door.assign(g.size(), 0);
  g.door[g.index(0, 0)] = 1;
  const NavGrid out = inflate(g, 0.12);
  size_t n = 0;
  for (size_t y = 0; y < 21; ++y)
    for (size_t x = 0; x < 21; ++x) {
      const double d = (g.centre(x, y) - g.centre(10, 10)).norm();
      EXPECT_EQ(out.occupied[g.index(x, y)], d < 0.12 ? 1 : 0) << x << ", " << y;
      n += out.occupied[g.index(x, y)];
    }
  EXPECT_EQ(n, 21u);  // dx^2 + dy^2 < 5.76: the centre, 4 + 4 + 4 + 8 around it
  EXPECT_EQ(out.door, g.door);
  const std::vector<float> d = obstacleDistance(g);
  EXPECT_NEAR(d[g.index(12, 11)], std::sqrt(5.0) * 0.05, 1e-6);
  EXPECT_TRUE(std::isinf(obstacleDistance(grid(3, 3))[4]));
}

TEST(NavWavefront, BadInputNamesTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  NavGrid g = grid(10, 10);
  Wavefront w;
  EXPECT_NE(thrown([&] { w.plan(g, {}, {nan, 0.1}, {0.2, 0.2}); }).find("start is not finite: (nan"), std::string::npos);
  EXPECT_NE(thrown([&] { w.plan(g, {}, {0.1, 0.1}, {0.2, inf}); }).find("goal is not finite"), std::string::npos);
  NavGrid r = g;
  r.resolution = -0.05;
  const std::string res = thrown([&] { w.plan(r, {}, {0.1, 0.1}, {0.2, 0.2}); });
  EXPECT_NE(res.find("resolution must be > 0 and finite, got -0.05"), std::string::npos) << res;
  NavGrid o = g;
  o.occupied.resize(99);
  EXPECT_NE(thrown([&] { inflate(o, 0.1); }).find("occupied has 99 cells, width * height is 100"), std::string::npos);
  NavGrid dd = g;
  dd.door.assign(7, 0);
  EXPECT_NE(thrown([&] { dd.validate(); }).find("door has 7 cells"), std::string::npos);
  EXPECT_NE(thrown([&] { inflate(g, nan); }).find("radius"), std::string::npos);
  EXPECT_NE(thrown([&] { BlockedCells().block(g, {100}, 0.0); }).find("cell 100 is outside"), std::string::npos);
  EXPECT_NE(thrown([&] { pathBlocked(g, {}, {{0.1, nan}}, 0, 1.0); }).find("path point"), std::string::npos);
  EXPECT_NE(thrown([&] { pathBlocked(g, {}, {{0.1, 0.1}}, 0, -1.0); }).find("ahead_m"), std::string::npos);
  WavefrontConfig c;
  c.clearance_weight = -1;
  EXPECT_NE(thrown([&] { Wavefront{c}; }).find("clearance_weight must be finite and >= 0, got -1"), std::string::npos);
  c = {};
  c.clearance_range = 0;
  EXPECT_NE(thrown([&] { Wavefront{c}; }).find("clearance_range"), std::string::npos);
  EXPECT_EQ(thrown([&] { w.plan(NavGrid{}, {}, {0, 0}, {0, 0}); }), "(nothing thrown)");  // empty: no cells
  EXPECT_EQ(w.plan(NavGrid{}, {}, {0, 0}, {0, 0}).why, "start outside the grid");
}

}  // namespace polyloc::t_nav_wavefront
