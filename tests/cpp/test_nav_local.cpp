// polynav's local obstacle avoidance with known geometry and known answers: the rectangular hull's
// extents and clearances, Nearness Diagram's situations (HSGR, HSWR, HSNR, LS1, LS2, Blocked) and
// directions in open space, beside a wall, in corridors, at gaps a 0.5 m wide robot does and does
// not fit through; VFH through a gap and fully blocked; errors that name the field.
#include <polynav/hull.hpp>
#include <polynav/local_command.hpp>
#include <polynav/nearness_diagram.hpp>
#include <polynav/polar_scan.hpp>
#include <polynav/vfh.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_nav_local {

using namespace polynav;
using Eigen::Vector2d;


constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = M_PI / 180;
using Segment = std::pair<Vector2d, Vector2d>;

// A full-turn scan of 1-degree beams from -pi (beam 180 straight ahead, 270 to the left) of the
// segments in the base frame, by exact ray-segment intersection; nothing: +inf.
PolarScan scanOf(const std::vector<Segment>& segments, double range_max = 5.0) {
  PolarScan s;
  s.angle_min = -M_PI, s.angle_increment = 2 * M_PI / 360, s.range_max = range_max;
  s.ranges.assign(360, float(kInf));
  for (size_t i = 0; i < 360; ++i) {
    const Vector2d d(std::cos(s.angle(i)), std::sin(s.angle(i)));
    for (const auto& [a, b] : segments) {
      const Vector2d e = b - a;
      const double den = d.x() * (-e.y()) - d.y() * (-e.x());
      if (std::abs(den) < 1e-12) continue;
      const double t = (a.x() * (-e.y()) - a.y() * (-e.x())) / den;  // along the beam
      const double u = (d.x() * a.y() - d.y() * a.x()) / den;          // along the segment
      if (t > 0 && u >= 0 && u <= 1 && t <= range_max && t < s.ranges[i]) s.ranges[i] = float(t);
    }
  }
  return s;
}

// A wall across the path at x (1.5 m ahead unless given) from y0 to y1, with gaps [g0, g1) cut out.
std::vector<Segment> wall(double y0, double y1, std::vector<std::pair<double, double>> gaps = {}, double x = 1.5) {
  std::vector<Segment> out;
  double y = y0;
  for (auto [g0, g1] : gaps) {
    out.push_back({{x, y}, {x, g0}});
    y = g1;
  }
  out.push_back({{x, y}, {x, y1}});
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

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

const RectHull kHull;  // 0.6 x 0.5 m: front = rear = 0.3, left = right = 0.25


TEST(RectHull, ExtentAlongTheAxesAndCorners) {
  const RectHull h{0.4, 0.2, 0.3, 0.1};  // all sides different, so that a swap shows
  EXPECT_NEAR(h.extent(0), 0.4, 1e-12);
  EXPECT_NEAR(h.extent(M_PI / 2), 0.3, 1e-12);
  EXPECT_NEAR(h.extent(M_PI), 0.2, 1e-12);
  EXPECT_NEAR(h.extent(-M_PI), 0.2, 1e-12);
  EXPECT_NEAR(h.extent(-M_PI / 2), 0.1, 1e-12);
  EXPECT_NEAR(h.extent(3 * M_PI / 2), 0.1, 1e-12);  // any turn
  EXPECT_NEAR(h.extent(std::atan2(0.3, 0.4)), 0.5, 1e-12);  // front-left corner: 3-4-5
  EXPECT_NEAR(h.extent(std::atan2(-0.1, -0.2)), std::sqrt(0.05), 1e-12);  // rear-right corner
  EXPECT_NEAR(h.extent(30 * kDeg), 0.4 / std::cos(30 * kDeg), 1e-12);  // through the front side
  EXPECT_NEAR(h.extent(60 * kDeg), 0.3 / std::sin(60 * kDeg), 1e-12);  // through the left side
  EXPECT_TRUE(std::isnan(h.extent(std::nan(""))));
  EXPECT_NEAR(h.width(), 0.4, 1e-12);
  // The gap to the body, not to the centre: 0.35 m to the side is 0.10 m away, 0.35 m ahead 0.05 m.
  EXPECT_NEAR(kHull.clearance(M_PI / 2, 0.35), 0.10, 1e-12);
  EXPECT_NEAR(kHull.clearance(0, 0.35), 0.05, 1e-12);
  EXPECT_NEAR(kHull.clearance(std::atan2(0.25, 0.3), 1.0), 1.0 - std::hypot(0.3, 0.25), 1e-12);
  EXPECT_LT(kHull.clearance(0, 0.2), 0);  // inside the hull
}

TEST(RectHull, FromFootprintIsTheBoundingRectangleHoldingTheOrigin) {
  const RectHull h = RectHull::fromFootprint({{0.5, 0.2}, {0.5, -0.3}, {-0.1, -0.3}, {-0.1, 0.2}, {0.6, 0}});
  EXPECT_DOUBLE_EQ(h.front, 0.6);
  EXPECT_DOUBLE_EQ(h.rear, 0.1);
  EXPECT_DOUBLE_EQ(h.left, 0.2);
  EXPECT_DOUBLE_EQ(h.right, 0.3);
  const RectHull g = RectHull::fromFootprint({{0.2, 0.1}, {0.6, 0.1}, {0.6, 0.4}});  // the origin outside
  EXPECT_DOUBLE_EQ(g.front, 0.6);
  EXPECT_DOUBLE_EQ(g.rear, 0);
  EXPECT_DOUBLE_EQ(g.left, 0.4);
  EXPECT_DOUBLE_EQ(g.right, 0);
}

TEST(RectHull, BadInputNamesTheField) {
  EXPECT_TRUE(has(thrown([] { RectHull::fromFootprint({}); }), "footprint is empty"));
  EXPECT_TRUE(has(thrown([] { RectHull::fromFootprint({{0.1, 0.1}, {std::nan(""), 0}}); }), "footprint vertex 1"));
  EXPECT_TRUE(has(thrown([] { RectHull{0.3, 0.3, -0.1, 0.25}.validate(); }), "left must be finite and >= 0, got -0.1"));
  EXPECT_TRUE(has(thrown([] { RectHull{kInf, 0.3, 0.25, 0.25}.validate(); }), "front"));
  EXPECT_EQ(thrown([] { kHull.validate(); }), "(nothing thrown)");
}

TEST(NearnessDiagram, PolarScanHelpers) {
  PolarScan s = scanOf({});
  EXPECT_NEAR(s.angle(180), 0, 1e-12);
  EXPECT_NEAR(s.angle(270), M_PI / 2, 1e-12);
  EXPECT_EQ(s.indexOf(0), 180u);
  EXPECT_EQ(s.indexOf(0.4 * kDeg), 180u);
  EXPECT_EQ(s.indexOf(0.6 * kDeg), 181u);
  EXPECT_EQ(s.indexOf(2 * M_PI + 0.6 * kDeg), 181u);
  EXPECT_EQ(s.indexOf(M_PI), 0u);                  // -pi and pi are one direction
  EXPECT_EQ(s.indexOf(M_PI - 0.4 * kDeg), 0u);     // wraps past the last beam (179 deg)
  EXPECT_EQ(s.indexOf(M_PI - 0.6 * kDeg), 359u);
  EXPECT_FALSE(s.indexOf(std::nan("")).has_value());
  s.ranges[180] = 1.5f, s.ranges[181] = 0, s.ranges[182] = std::nanf(""), s.ranges[183] = 6;
  EXPECT_TRUE(s.hit(180));
  EXPECT_FALSE(s.hit(181));  // no reading
  EXPECT_FALSE(s.hit(182));
  EXPECT_FALSE(s.hit(183));  // beyond range_max: nothing there
  EXPECT_FALSE(s.hit(0));
  EXPECT_NEAR(s.point(180).x(), 1.5, 1e-6);
  EXPECT_NEAR(s.point(180).y(), 0, 1e-6);
  PolarScan front;  // 270 degrees, -135 .. 135
  front.angle_min = -135 * kDeg, front.angle_increment = kDeg, front.range_max = 5, front.ranges.assign(271, 1.0f);
  EXPECT_FALSE(front.fullCircle());
  EXPECT_TRUE(s.fullCircle());
  EXPECT_EQ(front.indexOf(135.4 * kDeg), 270u);
  EXPECT_EQ(front.indexOf(-135.4 * kDeg), 0u);
  EXPECT_FALSE(front.indexOf(-136 * kDeg).has_value());
  EXPECT_FALSE(front.indexOf(M_PI).has_value());
}

TEST(NearnessDiagram, OpenSpaceGoalAheadIsHSGRAtFullSpeed) {
  PolarScan s = scanOf({});
  s.ranges[10] = std::nanf(""), s.ranges[20] = 7.0f;  // not finite, beyond range_max: nothing there
  const NdCommand c = nearnessDiagram(s, {3, 0}, kHull);
  EXPECT_EQ(c.situation, NdSituation::HSGR);
  EXPECT_DOUBLE_EQ(c.v, 0.5);
  EXPECT_NEAR(c.w, 0, 1e-12);
  EXPECT_NEAR(c.direction, 0, 1e-12);
  EXPECT_EQ(c.min_clearance, kInf);
  EXPECT_FALSE(c.blocked);
  const NdCommand l = nearnessDiagram(s, {2, 2}, kHull, {}, {0.8, 2.0});  // 45 degrees left
  EXPECT_NEAR(l.direction, M_PI / 4, 1e-12);
  EXPECT_NEAR(l.v, 0.8 * std::cos(M_PI / 4), 1e-12);
  EXPECT_NEAR(l.w, 2.0 * 0.5, 1e-12);
  const NdCommand here = nearnessDiagram(s, {0, 0}, kHull);
  EXPECT_EQ(here.v, 0);
  EXPECT_EQ(here.w, 0);
}

TEST(NearnessDiagram, GoalBehindTurnsInPlaceTowardsIt) {
  const PolarScan s = scanOf({});
  const NdCommand l = nearnessDiagram(s, {-2, 0.5}, kHull);
  EXPECT_EQ(l.situation, NdSituation::HSGR);
  EXPECT_EQ(l.v, 0);
  EXPECT_DOUBLE_EQ(l.w, 1.0);  // clamped to max_yaw_rate, counter-clockwise
  EXPECT_NEAR(l.direction, std::atan2(0.5, -2), 1e-12);
  const NdCommand r = nearnessDiagram(s, {-2, -0.5}, kHull);
  EXPECT_EQ(r.v, 0);
  EXPECT_DOUBLE_EQ(r.w, -1.0);
  const NdCommand side = nearnessDiagram(s, {0, -2}, kHull);  // exactly 90 degrees: no speed, w = -max
  EXPECT_NEAR(side.v, 0, 1e-12);
  EXPECT_NEAR(side.w, -1.0, 1e-12);
  // A 270-degree scan that cannot see behind: still turns towards the goal.
  PolarScan front;
  front.angle_min = -135 * kDeg, front.angle_increment = kDeg, front.range_max = 5, front.ranges.assign(271, kInf);
  const NdCommand f = nearnessDiagram(front, {-2, 0.5}, kHull);
  EXPECT_EQ(f.v, 0);
  EXPECT_DOUBLE_EQ(f.w, 1.0);
}

TEST(NearnessDiagram, WallBesideTheLeftIsLS1TurningAway) {
  // 0.2 m from the hull's left side (0.45 m from the centre), inside the 0.3 m security zone.
  const NdCommand c = nearnessDiagram(scanOf({{{-10, 0.45}, {10, 0.45}}}), {3, 0}, kHull);
  EXPECT_EQ(c.situation, NdSituation::LS1) << situationName(c.situation);
  EXPECT_NEAR(c.min_clearance, 0.2, 1e-6);
  // 90 degrees from the obstacle at 0.3 m, 180 at contact: 120 degrees at 0.2 m, i.e. 30 right.
  EXPECT_NEAR(c.direction, -30 * kDeg, 1e-5);
  EXPECT_LT(c.w, 0);
  EXPECT_NEAR(c.w, -1.0 / 3, 1e-5);
  EXPECT_NEAR(c.v, 0.5 * (0.2 / 0.3) * std::cos(30 * kDeg), 1e-5);
  // Mirrored: a wall on the right turns it left.
  const NdCommand m = nearnessDiagram(scanOf({{{-10, -0.45}, {10, -0.45}}}), {3, 0}, kHull);
  EXPECT_EQ(m.situation, NdSituation::LS1);
  EXPECT_NEAR(m.direction, 30 * kDeg, 1e-5);
  // 0.4 m from the hull: outside the zone, straight on at full speed.
  const NdCommand far = nearnessDiagram(scanOf({{{-10, 0.65}, {10, 0.65}}}), {3, 0}, kHull);
  EXPECT_EQ(far.situation, NdSituation::HSGR);
  EXPECT_DOUBLE_EQ(far.v, 0.5);
}

TEST(NearnessDiagram, CorridorIsLS2Centred) {
  // 0.9 m wide: 0.2 m each side of the 0.5 m hull.
  const NdCommand c = nearnessDiagram(scanOf({{{-10, 0.45}, {10, 0.45}}, {{-10, -0.45}, {10, -0.45}}}), {3, 0}, kHull);
  EXPECT_EQ(c.situation, NdSituation::LS2) << situationName(c.situation);
  EXPECT_NEAR(c.direction, 0, 1e-6);
  EXPECT_NEAR(c.w, 0, 1e-6);
  EXPECT_NEAR(c.v, 0.5 * 0.2 / 0.3, 1e-5);
  // 0.05 m off the middle (0.25 m left, 0.15 m right): turned back towards it by (pi/4) x 0.1 / 0.3.
  const NdCommand o = nearnessDiagram(scanOf({{{-10, 0.5}, {10, 0.5}}, {{-10, -0.4}, {10, -0.4}}}), {3, 0}, kHull);
  EXPECT_EQ(o.situation, NdSituation::LS2);
  EXPECT_NEAR(o.direction, 15 * kDeg, 1e-4);
  EXPECT_GT(o.w, 0);
  EXPECT_NEAR(o.min_clearance, 0.15, 1e-6);
}

TEST(NearnessDiagram, GapRightOfTheGoalIsHSNRThroughTheGap) {
  // A wall 1.5 m ahead across the goal's direction, a 1.0 m gap from y = -1.45 to -0.45.
  const NdCommand c = nearnessDiagram(scanOf(wall(-3.05, 3.05, {{-1.45, -0.45}})), {4, 0}, kHull);
  EXPECT_EQ(c.situation, NdSituation::HSNR) << situationName(c.situation);
  EXPECT_NEAR(c.min_clearance, 1.2, 1e-6);
  // The valley's middle, within a few degrees of the gap's centre.
  EXPECT_NEAR(c.direction, std::atan2(-0.95, 1.5), 3 * kDeg);
  EXPECT_GT(c.direction, std::atan2(-1.45, 1.5));
  EXPECT_LT(c.direction, std::atan2(-0.45, 1.5));
  EXPECT_GT(c.v, 0);
  EXPECT_LT(c.w, 0);
  // The goal straight through the gap: the straight path is clear, HSGR.
  const NdCommand g = nearnessDiagram(scanOf(wall(-3.05, 3.05, {{-1.45, -0.45}})), {4.5, -2.85}, kHull);
  EXPECT_EQ(g.situation, NdSituation::HSGR);
  EXPECT_NEAR(g.direction, std::atan2(-2.85, 4.5), 1e-12);
}

TEST(NearnessDiagram, GapNarrowerThanTheHullIsNotNavigable) {
  // 0.4 m straight ahead: the 0.5 m hull does not fit; ND goes round the wall's end instead.
  const NdCommand c = nearnessDiagram(scanOf(wall(-3.05, 3.05, {{-0.2, 0.2}})), {4, 0}, kHull);
  EXPECT_EQ(c.situation, NdSituation::HSWR) << situationName(c.situation);
  EXPECT_GT(std::abs(c.direction), 90 * kDeg);  // past a wall end at 63 degrees, 45 into the valley
  EXPECT_EQ(c.v, 0);
  // A wall beyond range_max both ways: no other way, Blocked.
  const NdCommand b = nearnessDiagram(scanOf(wall(-30, 30, {{-0.2, 0.2}})), {4, 0}, kHull);
  EXPECT_EQ(b.situation, NdSituation::Blocked) << situationName(b.situation);
  EXPECT_TRUE(b.blocked);
  EXPECT_EQ(b.v, 0);
  EXPECT_EQ(b.w, 0);
  // 0.7 m does fit: straight through.
  const NdCommand w = nearnessDiagram(scanOf(wall(-30, 30, {{-0.35, 0.35}})), {4, 0}, kHull);
  EXPECT_EQ(w.situation, NdSituation::HSGR) << situationName(w.situation);
  EXPECT_NEAR(w.direction, 0, 1e-12);
  EXPECT_DOUBLE_EQ(w.v, 0.5);
  // 0.7 m but off the goal's line: the valley through it (HSNR), not Blocked.
  const NdCommand o = nearnessDiagram(scanOf(wall(-30, 30, {{-1.1, -0.4}})), {4, 0}, kHull);
  EXPECT_EQ(o.situation, NdSituation::HSNR) << situationName(o.situation);
  EXPECT_NEAR(o.direction, std::atan2(-0.75, 1.5), 3 * kDeg);
}

TEST(NearnessDiagram, GoalBehindAnObstacleWithAWideRegionIsHSWR) {
  // A wall ahead from y = -1.03 to 3.05: the way round its right end (at -34.5 degrees) is a wide
  // valley; HSWR heads half of 90 degrees into it from its edge beam at -35 degrees.
  const NdCommand c = nearnessDiagram(scanOf(wall(-1.03, 3.05)), {4, 0}, kHull);
  EXPECT_EQ(c.situation, NdSituation::HSWR) << situationName(c.situation);
  EXPECT_NEAR(c.direction, -80 * kDeg, 1e-9);
  EXPECT_NEAR(c.v, 0.5 * std::cos(80 * kDeg), 1e-9);
  EXPECT_NEAR(c.w, -80.0 / 90, 1e-9);
  // A narrower smax: 60 degrees -> 30 into the valley.
  const NdCommand n = nearnessDiagram(scanOf(wall(-1.03, 3.05)), {4, 0}, kHull, {0.3, 60});
  EXPECT_NEAR(n.direction, -65 * kDeg, 1e-9);
  // The goal in front of that wall is reached straight.
  const NdCommand g = nearnessDiagram(scanOf(wall(-1.03, 3.05)), {1.0, 0.2}, kHull);
  EXPECT_EQ(g.situation, NdSituation::HSGR);
  EXPECT_NEAR(g.direction, std::atan2(0.2, 1.0), 1e-12);
}

TEST(NearnessDiagram, TheRectangularHullDecidesSafety) {
  const Vector2d goal(3, 0);
  // A 0.1 m post 0.35 m to the left of the centre: 0.10 m from the hull's side: low safety.
  const NdCommand side = nearnessDiagram(scanOf({{{-0.05, 0.35}, {0.05, 0.35}}}), goal, kHull);
  EXPECT_EQ(side.situation, NdSituation::LS1) << situationName(side.situation);
  EXPECT_NEAR(side.min_clearance, 0.10, 1e-6);
  EXPECT_LT(side.w, 0);
  // 0.35 m ahead: 0.05 m from the front: low safety too.
  const NdCommand ahead = nearnessDiagram(scanOf({{{0.35, -0.05}, {0.35, 0.05}}}), goal, kHull);
  EXPECT_TRUE(ahead.situation == NdSituation::LS1 || ahead.situation == NdSituation::LS2)
      << situationName(ahead.situation);
  EXPECT_NEAR(ahead.min_clearance, 0.05, 1e-6);
  EXPECT_NEAR(ahead.v, 0.5 * (0.05 / 0.3) * std::max(0.0, std::cos(ahead.direction)), 1e-6);
  // 0.6 m ahead: 0.3 m from the front, not inside the zone (a 0.39 m circle round the corners
  // would put it 0.21 m away); the post still stands in the way: round it in high safety.
  const NdCommand far = nearnessDiagram(scanOf({{{0.6, -0.05}, {0.6, 0.05}}}), goal, kHull);
  EXPECT_EQ(far.situation, NdSituation::HSWR) << situationName(far.situation);
  EXPECT_NEAR(far.min_clearance, 0.3, 1e-6);
  // 0.55 m ahead: 0.25 m, inside again.
  const NdCommand near = nearnessDiagram(scanOf({{{0.55, -0.05}, {0.55, 0.05}}}), goal, kHull);
  EXPECT_EQ(near.situation, NdSituation::LS1) << situationName(near.situation);
  // A narrower hull front with the same post 0.35 m ahead: 0.2 m away.
  const NdCommand short_front = nearnessDiagram(scanOf({{{0.35, -0.05}, {0.35, 0.05}}}), goal, RectHull{0.15, 0.3, 0.25, 0.25});
  EXPECT_NEAR(short_front.min_clearance, 0.2, 1e-6);
}

TEST(NearnessDiagram, BadInputNamesTheField) {
  const PolarScan s = scanOf({});
  const double nan = std::nan("");
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(s, {nan, 0}, kHull); }), "goal_in_base is not finite"));
  PolarScan empty = s;
  empty.ranges.clear();
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(empty, {1, 0}, kHull); }), "scan.ranges is empty"));
  PolarScan inc = s;
  inc.angle_increment = 0;
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(inc, {1, 0}, kHull); }), "scan.angle_increment must be > 0"));
  inc.angle_increment = 2 * kDeg;  // 360 beams of 2 degrees: twice round
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(inc, {1, 0}, kHull); }), "exceeds a full turn"));
  PolarScan rmax = s;
  rmax.range_max = -1;
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(rmax, {1, 0}, kHull); }), "scan.range_max"));
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(s, {1, 0}, kHull, {-0.1, 90}); }), "safety_distance must be finite and > 0, got -0.1"));
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(s, {1, 0}, kHull, {0.3, -5}); }), "wide_valley_deg"));
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(s, {1, 0}, kHull, {}, {-1, 1}); }), "max_speed"));
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(s, {1, 0}, kHull, {}, {0.5, nan}); }), "max_yaw_rate"));
  EXPECT_TRUE(has(thrown([&] { nearnessDiagram(s, {1, 0}, RectHull{0.3, -0.3, 0.25, 0.25}); }), "rear"));
  EXPECT_STREQ(situationName(NdSituation::HSGR), "HSGR");
  EXPECT_STREQ(situationName(NdSituation::LS2), "LS2");
  EXPECT_STREQ(situationName(NdSituation::Blocked), "Blocked");
}

TEST(Vfh, OpenSpaceGoalAheadIsStraight) {
  const LocalCommand c = vfh(scanOf({}), {3, 0}, kHull);
  EXPECT_NEAR(c.direction, 0, 1e-12);
  EXPECT_DOUBLE_EQ(c.v, 0.5);
  EXPECT_NEAR(c.w, 0, 1e-12);
  EXPECT_FALSE(c.blocked);
  const LocalCommand b = vfh(scanOf({}), {-2, 0.5}, kHull);  // behind: turn in place
  EXPECT_EQ(b.v, 0);
  EXPECT_DOUBLE_EQ(b.w, 1.0);
  // A wall 2 m to the side (1.75 m from the hull) is outside the blocking nearness: still straight.
  const LocalCommand w = vfh(scanOf({{{-10, 2}, {10, 2}}}), {3, 0}, kHull);
  EXPECT_NEAR(w.direction, 0, 1e-12);
  EXPECT_NEAR(w.min_clearance, 1.75, 1e-6);
  // A wall 2 m ahead, 1.7 m from the front: nearness 1 - 1.7 / 2 = 0.15, below the threshold: not
  // blocked, but it slows the robot to (1 - 0.15) x max_speed.
  const LocalCommand a = vfh(scanOf({{{2, -5}, {2, 5}}}), {4, 0}, kHull);
  EXPECT_FALSE(a.blocked);
  EXPECT_NEAR(a.direction, 0, 1e-12);
  EXPECT_NEAR(a.v, 0.5 * 0.85, 1e-6);
}

TEST(Vfh, WallWithAGapGoesThroughTheGap) {
  // A wall 1.0 m ahead (within the blocking nearness on both sides of the gap: VFH+ sees only
  // obstacles nearer than (1 - threshold) x window_m = 1.5 m from the hull), a 1.0 m gap from
  // y = -1.05 to -0.05. Enlarged by 0.35 m its edges leave the sectors at -30 and -25 degrees free.
  const LocalCommand c = vfh(scanOf(wall(-3.05, 3.05, {{-1.05, -0.05}}, 1.0)), {4, 0}, kHull);
  EXPECT_FALSE(c.blocked);
  EXPECT_NEAR(c.direction, -27.5 * kDeg, 1e-9);  // the narrow run's middle
  EXPECT_GT(c.direction, std::atan2(-1.05, 1.0));
  EXPECT_LT(c.direction, std::atan2(-0.05, 1.0));
  EXPECT_NEAR(c.direction, std::atan2(-0.55, 1.0), 2 * kDeg);
  EXPECT_GT(c.v, 0);
  EXPECT_LT(c.w, 0);
  // 0.4 m straight ahead: too narrow for the 0.5 m hull; VFH does not aim into it.
  const LocalCommand n = vfh(scanOf(wall(-30, 30, {{-0.2, 0.2}})), {4, 0}, kHull);
  EXPECT_GT(std::abs(n.direction), 20 * kDeg);
}

TEST(Vfh, AllBlockedStops) {
  PolarScan s = scanOf({});
  std::fill(s.ranges.begin(), s.ranges.end(), 0.8f);  // a ring 0.8 m round the centre
  const LocalCommand c = vfh(s, {3, 0}, kHull);
  EXPECT_TRUE(c.blocked);
  EXPECT_EQ(c.v, 0);
  EXPECT_EQ(c.w, 0);
  // Nearest near a corner's direction (39.8 degrees; the beams are 1 degree apart).
  EXPECT_GE(c.min_clearance, 0.8 - std::hypot(0.3, 0.25) - 1e-6);
  EXPECT_NEAR(c.min_clearance, 0.8 - std::hypot(0.3, 0.25), 3e-3);
}

TEST(Vfh, BadInputNamesTheField) {
  const PolarScan s = scanOf({});
  EXPECT_TRUE(has(thrown([&] { vfh(s, {std::nan(""), 0}, kHull); }), "goal_in_base"));
  EXPECT_TRUE(has(thrown([&] { vfh(s, {1, 0}, kHull, {0, 2, 0.25, 0.1, 80}); }), "sector_deg"));
  EXPECT_TRUE(has(thrown([&] { vfh(s, {1, 0}, kHull, {5, -2, 0.25, 0.1, 80}); }), "window_m"));
  EXPECT_TRUE(has(thrown([&] { vfh(s, {1, 0}, kHull, {5, 2, 1.0, 0.1, 80}); }), "threshold"));
  EXPECT_TRUE(has(thrown([&] { vfh(s, {1, 0}, kHull, {5, 2, 0.25, -0.1, 80}); }), "margin"));
  EXPECT_TRUE(has(thrown([&] { vfh(s, {1, 0}, kHull, {}, {0.5, -1}); }), "max_yaw_rate"));
  PolarScan empty = s;
  empty.ranges.clear();
  EXPECT_TRUE(has(thrown([&] { vfh(empty, {1, 0}, kHull); }), "scan.ranges is empty"));
}

}  // namespace polyloc::t_nav_local
