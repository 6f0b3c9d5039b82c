// polynav's navigation zones: polygons (winding, non-convex, boundaries), rooms, door regions to
// the centimetre, the footprint against danger zones, door passages and approach poses, zone files
// whose errors name file, line and key, the lab's zone file against the lab map (generator doors,
// every "danger" triangle covered, every goal clear of the map by 0.1 m) and the rasterisers.
#include <polynav/nav_grid.hpp>
#include <polynav/zones.hpp>

#include <polyloc/config/robot.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mapgen/generate.hpp>
#include <polyloc/sim/body_collision.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_nav_zones {

using namespace polynav;
using Eigen::Vector2d;
using Eigen::Vector3d;


const std::string kLabZones = std::string(POLYLOC_SOURCE_DIR) + "/maps/nav/lab.yaml";
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kPi = M_PI;

// The robot of the brief: 0.6 m long (x), 0.5 m wide, base_link in its centre.
Polygon robot(double length = 0.6, double width = 0.5) {
  return {{length / 2, width / 2}, {-length / 2, width / 2}, {-length / 2, -width / 2}, {length / 2, -width / 2}};
}

Polygon rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

std::string thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// What loading `text` as a zone file throws (its path in `path`).
std::string loadError(const polyloc::test::TempDir& dir, const std::string& text, std::string* path = nullptr) {
  const std::string f = dir.write("zones.yaml", text);
  if (path) *path = f;
  try {
    loadZones(f);
  } catch (const ZonesError& e) {
    return e.what();
  }
  return "(nothing thrown)";
}


// --------------------------------------------------------------------------------------- polygons

TEST(NavZones, PointInNonConvexPolygonEitherWinding) {
  const Polygon l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};  // an L, counter-clockwise
  const Polygon r(l.rbegin(), l.rend());                              // the same, clockwise
  for (const Polygon& p : {l, r}) {
    EXPECT_TRUE(pointInPolygon(p, {0.5, 1.5}));
    EXPECT_TRUE(pointInPolygon(p, {1.5, 0.5}));
    EXPECT_FALSE(pointInPolygon(p, {1.5, 1.5}));  // the notch
    EXPECT_FALSE(pointInPolygon(p, {-0.01, 1.0}));
    EXPECT_TRUE(pointInPolygon(p, {1.0, 1.5}));   // on the inner edge: inside
    EXPECT_TRUE(pointInPolygon(p, {1.0, 1.0}));   // on the reflex corner
    EXPECT_TRUE(pointInPolygon(p, {2.0, 0.0}));   // on a corner
    EXPECT_FALSE(pointInPolygon(p, {kNaN, 0.5}));
    EXPECT_DOUBLE_EQ(polygonDistance(p, {1.5, 1.5}), 0.5);
    EXPECT_DOUBLE_EQ(polygonDistance(p, {0.5, 0.5}), 0.0);
    EXPECT_DOUBLE_EQ(polygonDistance(p, {3.0, 0.5}), 1.0);
  }
  EXPECT_EQ(polygonProblem(l), "");
  EXPECT_NE(polygonProblem({{0, 0}, {1, 1}, {1, 0}, {0, 1}}).find("not a simple polygon"), std::string::npos);  // bow tie
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}}).find("needs at least 3"), std::string::npos);
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}, {1, 0}, {0, 1}}).find("coincide"), std::string::npos);
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}, {1, 1e-13}}).find("no area"), std::string::npos);
  EXPECT_NE(polygonProblem({{0, 0}, {1, 0}, {2, 0}}).find("turns back"), std::string::npos);  // collinear
  EXPECT_NE(polygonProblem({{0, 0}, {2, 0}, {1, 0}, {1, 1}}).find("turns back"), std::string::npos);
  EXPECT_NE(polygonProblem({{0, 0}, {1, kNaN}, {0, 1}}).find("not finite"), std::string::npos);
}

TEST(NavZones, PolygonsOverlapCrossingTouchingContained) {
  const Polygon a = rect(0, 0, 1, 1);
  EXPECT_TRUE(polygonsOverlap(a, rect(0.5, 0.5, 2, 2)));     // edges cross
  EXPECT_TRUE(polygonsOverlap(a, rect(1, 0, 2, 1)));         // touching along an edge
  EXPECT_TRUE(polygonsOverlap(a, rect(0.2, 0.2, 0.4, 0.4)));  // inside, no edge meets
  EXPECT_TRUE(polygonsOverlap(rect(0.2, 0.2, 0.4, 0.4), a));
  EXPECT_FALSE(polygonsOverlap(a, rect(1.01, 0, 2, 1)));
  // A U; a box standing in its gap without touching overlaps nothing though the boxes' bounds do.
  const Polygon u = {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  EXPECT_FALSE(polygonsOverlap(u, rect(1.1, 1.1, 1.9, 2.9)));
  EXPECT_TRUE(polygonsOverlap(u, rect(1.1, 0.9, 1.9, 2.9)));
}

// ----------------------------------------------------------------------------------- lab queries

TEST(NavZones, RoomsAndCorridorAtKnownPoints) {
  const Zones z = loadZones(kLabZones);
  EXPECT_EQ(z.roomAt({3, 8}), "lab 1");
  EXPECT_EQ(z.roomAt({9, 8}), "lab 2");
  EXPECT_EQ(z.roomAt({16, 8}), "lab 3");
  EXPECT_EQ(z.roomAt({10, 1.5}), "corridor");
  EXPECT_EQ(z.roomAt({22, 2}), "loading hall");
  EXPECT_EQ(z.roomAt({22, 12}), "loading hall");
  EXPECT_EQ(z.roomAt({5.0, 3.49}), "corridor");
  EXPECT_EQ(z.roomAt({5.0, 3.51}), "lab 1");
  EXPECT_EQ(z.roomAt({6.5, 8}), "lab 1");  // on the partition: the first room listed
  EXPECT_EQ(z.roomAt({-0.5, 5}), "");
  EXPECT_EQ(z.roomAt({kNaN, 5}), "");

  ASSERT_EQ(z.corridors.size(), 1u);
  EXPECT_EQ(z.corridors[0].axis, Vector2d(1, 0));
  EXPECT_EQ(z.corridorAt({10, 1.5}), 0u);
  EXPECT_EQ(z.corridorAt({5.0, 2.85}), 0u);               // just short of lab 1's door region
  EXPECT_EQ(z.corridorAt({5.0, 3.2}), std::nullopt);      // in the door region's notch
  EXPECT_EQ(z.corridorAt({6.5, 3.2}), 0u);                // between the doors
  EXPECT_EQ(z.corridorAt({22, 2}), std::nullopt);         // the hall
  EXPECT_EQ(z.corridorAt({kNaN, 1}), std::nullopt);
}

TEST(NavZones, DoorRegionsToTheCentimetre) {
  const Zones z = loadZones(kLabZones);
  size_t open = 0;
  for (size_t i = 0; i < z.doors.size(); ++i) {
    const Door& d = z.doors[i];
    if (d.closed) {
      EXPECT_EQ(z.doorAt(d.centre), std::nullopt) << d.name;  // a closed door has no region
      continue;
    }
    ++open;
    const Vector2d a = d.along, n = d.normal();
    for (double s : {-1.0, 1.0}) {
      EXPECT_EQ(z.doorAt(d.centre), i) << d.name;
      EXPECT_EQ(z.doorAt(d.centre + s * a * (d.width / 2 - 0.01)), i) << d.name;
      EXPECT_EQ(z.doorAt(d.centre + s * a * (d.width / 2 + 0.01)), std::nullopt) << d.name;
      EXPECT_EQ(z.doorAt(d.centre + s * n * (d.depth - 0.01)), i) << d.name;
      EXPECT_EQ(z.doorAt(d.centre + s * n * (d.depth + 0.01)), std::nullopt) << d.name;
      EXPECT_EQ(z.doorAt(d.centre + s * (a * (d.width / 2 - 0.01) + n * (d.depth - 0.01))), i) << d.name;
      EXPECT_EQ(z.doorAt(d.centre + s * (a * (d.width / 2 + 0.01) + n * (d.depth - 0.01))), std::nullopt) << d.name;
    }
  }
  EXPECT_EQ(open, 3u);
  EXPECT_EQ(z.doorAt({5.0, 3.5 + 0.59}), z.doorIndex("lab 1"));
  EXPECT_EQ(z.doorAt({5.0, 3.5 - 0.61}), std::nullopt);
  EXPECT_EQ(z.doorAt({kNaN, 3.5}), std::nullopt);

  // A door in a diagonal wall.
  Door d;
  d.name = "diagonal";
  d.centre = {1, 1};
  d.along = Vector2d(1, 1).normalized();
  d.width = 0.8;
  EXPECT_TRUE(d.contains(d.centre + d.along * 0.39 + d.normal() * 0.59));
  EXPECT_FALSE(d.contains(d.centre + d.along * 0.41));
  EXPECT_FALSE(d.contains(d.centre - d.normal() * 0.61));
}

TEST(NavZones, FootprintAgainstTheStairwell) {
  const Zones z = loadZones(kLabZones);
  ASSERT_EQ(z.danger.size(), 1u);
  const Polygon& s = z.danger[0].polygon;
  const double west = s[0].x(), south = s[0].y();  // 23.45, 3.55
  const Polygon fp = robot();
  // Facing east, the front edge 5 cm short of the zone's west edge / 5 cm into it.
  EXPECT_FALSE(z.inDanger(fp, {west - 0.3 - 0.05, 6.0, 0}));
  EXPECT_TRUE(z.inDanger(fp, {west - 0.3 + 0.05, 6.0, 0}));
  // Facing north below its south edge; then sideways (yaw 0: 0.25 m to the side).
  EXPECT_FALSE(z.inDanger(fp, {24.5, south - 0.3 - 0.05, kPi / 2}));
  EXPECT_TRUE(z.inDanger(fp, {24.5, south - 0.3 + 0.05, kPi / 2}));
  EXPECT_FALSE(z.inDanger(fp, {24.5, south - 0.25 - 0.05, 0}));
  EXPECT_TRUE(z.inDanger(fp, {24.5, south - 0.25 + 0.05, 0}));
  // Turned 45 degrees: the footprint reaches (0.3 + 0.25) / sqrt(2) = 0.389 m along x.
  const double reach = (0.3 + 0.25) / std::sqrt(2.0);
  EXPECT_FALSE(z.inDanger(fp, {west - reach - 0.05, south - 0.1, kPi / 4}));
  EXPECT_TRUE(z.inDanger(fp, {west - reach + 0.05, 5.0, kPi / 4}));
  EXPECT_TRUE(z.inDanger(fp, {24.7, 6.0, 0.3}));  // wholly inside: no edge crosses
  EXPECT_TRUE(z.inDanger(Vector2d(24.7, 6.0)));
  EXPECT_FALSE(z.inDanger(Vector2d(west - 0.01, 6.0)));
  EXPECT_NEAR(z.dangerDistance({west - 0.35, 6.0}), 0.35, 1e-12);
  EXPECT_EQ(z.dangerDistance({24.7, 6.0}), 0.0);
  EXPECT_EQ(Zones().dangerDistance({0, 0}), std::numeric_limits<double>::infinity());
  EXPECT_NE(thrown([&] { z.inDanger(Vector2d(kNaN, 0)); }).find("not finite"), std::string::npos);
  EXPECT_NE(thrown([&] { z.inDanger(fp, {0, 0, kNaN}); }).find("not finite"), std::string::npos);
  EXPECT_NE(thrown([&] { z.inDanger(Polygon{{0, 0}, {1, 0}}, {0, 0, 0}); }).find("at least 3"), std::string::npos);
  EXPECT_NE(thrown([&] { z.dangerDistance({0, kNaN}); }).find("not finite"), std::string::npos);
}

TEST(NavZones, DoorPassageAndApproachPose) {
  const Zones z = loadZones(kLabZones);
  const Door& lab1 = z.doors[*z.doorIndex("lab 1")];
  const DoorPassage in = doorPassage(lab1, {5.0, 1.5});  // from the corridor into lab 1
  EXPECT_TRUE(in.before.isApprox(Vector3d(5.0, 2.9, kPi / 2), 1e-12)) << in.before.transpose();
  EXPECT_TRUE(in.after.isApprox(Vector3d(5.0, 4.1, kPi / 2), 1e-12)) << in.after.transpose();
  const DoorPassage out = doorPassage(lab1, {2.0, 9.0});  // from lab 1 out, not in front of the door
  EXPECT_TRUE(out.before.isApprox(Vector3d(5.0, 4.1, -kPi / 2), 1e-12)) << out.before.transpose();
  EXPECT_TRUE(out.after.isApprox(Vector3d(5.0, 2.9, -kPi / 2), 1e-12)) << out.after.transpose();
  for (const Vector3d& p : {in.before, in.after, out.before, out.after})  // on the door region's edge
    EXPECT_NEAR((p.head<2>() - lab1.centre).norm(), lab1.depth, 1e-12);
  EXPECT_NE(thrown([&] { doorPassage(z.doors[*z.doorIndex("loading bay")], {25, 12}); }).find("closed"),
            std::string::npos);
  EXPECT_NE(thrown([&] { doorPassage(lab1, {kNaN, 0}); }).find("not finite"), std::string::npos);

  const GoalSpot& bench = z.goals[*z.goalIndex("lab 1 bench")];
  const Vector3d a = approachPose(bench);
  EXPECT_NEAR(a.x(), bench.pose.x() + 0.5, 1e-12);  // facing west: the approach lies east of it
  EXPECT_NEAR(a.y(), bench.pose.y(), 1e-12);
  EXPECT_EQ(a.z(), bench.pose.z());
  EXPECT_NEAR(std::abs(bench.pose.z()), kPi, 1e-12);
  GoalSpot g{"g", {1, 2, kPi / 2}, 0.3};
  EXPECT_TRUE(approachPose(g).isApprox(Vector3d(1, 1.7, kPi / 2), 1e-12));
}

// -------------------------------------------------------------------------------------- loading

TEST(NavZones, LoadErrorsNameFileLineAndKey) {
  const polyloc::test::TempDir dir;
  std::string f;
  auto expectError = [&](const std::string& text, int line, const std::string& key, const std::string& what) {
    const std::string e = loadError(dir, text, &f);
    EXPECT_NE(e.find(f + ":" + std::to_string(line) + ":"), std::string::npos) << e;
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  const std::string door = "doors:\n  - name: a\n    centre: [0, 0]\n    along: [1, 0]\n";
  expectError(door, 2, "doors[0]", "missing key 'width'");
  expectError(door + "    width: 0\n", 5, "doors[0].width", "must be > 0");
  expectError(door + "    width: -0.5\n", 5, "doors[0].width", "must be > 0");
  expectError(door + "    width: 0.8\n    widht: 0.8\n", 6, "doors[0]", "unknown key 'widht'");
  expectError(door + "    width: 0.8\n    width: 0.9\n", 6, "doors[0]", "key 'width' given twice");
  expectError(door + "    width: 0.8\n    depth: 0\n", 6, "doors[0].depth", "must be > 0");
  expectError(door + "    width: .nan\n", 5, "doors[0].width", "finite");
  expectError(door + "    width: 0.8\n    closed: maybe\n", 6, "doors[0].closed", "true or false");
  expectError("doors:\n  - {name: a, centre: [0, 0], along: [0, 0], width: 0.8}\n", 2, "doors[0].along",
              "must not be zero");
  expectError("doors:\n  - {name: a, centre: [0, 0, 1], along: [1, 0], width: 0.8}\n", 2, "doors[0].centre",
              "expected a point [x, y]");
  expectError("rooms:\n  - name: r\n    polygon: [[0, 0], [1, 0]]\n", 3, "rooms[0].polygon",
              "has 2 points, needs at least 3");
  expectError("rooms:\n  - name: r\n    polygon:\n      - [0, 0]\n      - [1, .inf]\n      - [0, 1]\n", 5,
              "rooms[0].polygon[1][1]", "expected a finite number, got '.inf'");
  expectError("rooms:\n  - name: r\n    polygon: [[0, 0], [1, nan], [0, 1]]\n", 3, "rooms[0].polygon[1][1]", "finite");
  expectError("rooms:\n  - name: r\n    polygon: [[0, 0], [1, 1], [1, 0], [0, 1]]\n", 3, "rooms[0].polygon",
              "not a simple polygon");
  expectError("rooms:\n  - {name: r, polygon: [[0, 0], [1, 0], [0, 1]]}\n  - {name: s, polygon: [[0, 0], [1, 0], [0, 1]]}\n"
              "  - {name: r, polygon: [[0, 0], [1, 0], [0, 1]]}\n",
              4, "rooms[2].name", "duplicate name 'r' (also rooms[0], line 2)");
  expectError("rooms:\n  - polygon: [[0, 0], [1, 0], [0, 1]]\n", 2, "rooms[0]", "missing key 'name'");
  expectError("corridors:\n  - name: c\n    polygon: [[0, 0], [1, 0], [0, 1]]\n    axis: [0, 0]\n", 4,
              "corridors[0].axis", "must not be zero");
  expectError("corridors:\n  - name: c\n    polygon: [[0, 0], [1, 0], [0, 1]]\n", 2, "corridors[0]",
              "missing key 'axis'");
  expectError("goals:\n  - {name: g, pose: [1, 2, 90]}\n  - {name: g, pose: [1, 3, 90]}\n", 3, "goals[1].name",
              "duplicate name 'g'");
  expectError("goals:\n  - {name: g, pose: [1, 2]}\n", 2, "goals[0].pose", "expected [x, y, yaw in degrees]");
  expectError("goals:\n  - {name: g, pose: [1, 2, north]}\n", 2, "goals[0].pose[2]", "angle");
  expectError("goals:\n  - {name: g, pose: [1, 2, 0], approach: -1}\n", 2, "goals[0].approach", "must be in [0, 10] m");
  expectError("rooms:\n  - {name: r, polygon: [[0, 0], [4, 0], [4, 3]]}\ngoals:\n  - {name: g, pose: [1e300, 2, 0]}\n", 4,
              "goals[0].pose", "the goal (1e+300, 2) lies more than 10 m outside the rooms and corridors");
  expectError("goals:\n  - {name: g, pose: [0.5, 0.5, 0]}\ndanger:\n  - {name: pit, polygon: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n",
              2, "goals[0].pose", "lies in danger zone 'pit'");
  expectError("goals:\n  - {name: g, pose: [1.3, 0.5, 0]}\ndanger:\n  - {name: pit, polygon: [[0, 0], [1, 0], [1, 1], [0, 1]]}\n",
              2, "goals[0].pose", "approach pose");
  expectError("rooms: []\ndoor: []\n", 2, "unknown key 'door'", "expected one of: rooms, doors");
  expectError("rooms: {name: r}\n", 1, "rooms", "expected a list");
  expectError("rooms:\n  - [0, 0]\n", 2, "rooms[0]", "expected a mapping");
  expectError("rooms: [\n  {name: r\n", 3, "", "YAML syntax error");

  EXPECT_NE(thrown([] { loadZones("/nonexistent/zones.yaml"); }).find("/nonexistent/zones.yaml: cannot open"),
            std::string::npos);
  // Every section is optional; degrees, or a unit.
  const Zones empty = loadZones(dir.write("empty.yaml", "# nothing here\n"));
  EXPECT_TRUE(empty.rooms.empty() && empty.doors.empty() && empty.goals.empty());
  const Zones g = loadZones(dir.write("g.yaml", "goals:\n  - {name: a, pose: [0, 0, 90]}\n  - {name: b, pose: [0, 0, 1 rad]}\n"
                                                "doors:\n  - {name: d, centre: [0, 0], along: [0, 2], width: 1}\n"));
  EXPECT_NEAR(g.goals[0].pose.z(), kPi / 2, 1e-12);
  EXPECT_NEAR(g.goals[1].pose.z(), 1.0, 1e-12);
  EXPECT_EQ(g.goals[0].approach, 0.5);
  EXPECT_EQ(g.doors[0].along, Vector2d(0, 1));  // normalised
  EXPECT_EQ(g.doors[0].depth, 0.6);
}

TEST(NavZones, ValidateZonesBuiltInCode) {
  Zones z = loadZones(kLabZones);
  EXPECT_NO_THROW(z.validate());
  Zones bad = z;
  bad.doors[1].along = {2, 0};
  EXPECT_NE(thrown([&] { bad.validate(); }).find("doors[1] 'lab 2': along (2, 0) must be a unit vector"),
            std::string::npos);
  bad = z;
  bad.rooms[0].polygon.resize(2);
  EXPECT_NE(thrown([&] { bad.validate(); }).find("rooms[0] 'corridor': polygon has 2 points"), std::string::npos);
  bad = z;
  bad.goals[0].pose = {24.7, 6.0, 0};
  EXPECT_NE(thrown([&] { bad.validate(); }).find("danger zone 'stairwell'"), std::string::npos);
  bad = z;
  bad.goals[1].name = bad.goals[0].name;
  EXPECT_NE(thrown([&] { bad.validate(); }).find("duplicate name"), std::string::npos);
  bad = z;
  bad.goals[0].pose = {1e300, 6.0, 0};  // finite, and no place
  EXPECT_NE(thrown([&] { bad.validate(); }).find("goals[0] '" + z.goals[0].name + "': the goal (1e+300, 6) lies more than 10 m outside"), std::string::npos);
  bad = z;
  bad.goals[0].approach = 1e300;
  EXPECT_NE(thrown([&] { bad.validate(); }).find("approach must be in [0, 10] m"), std::string::npos);
}

// ---------------------------------------------------------------------------- the lab, its map

TEST(NavZones, LabDoorsMatchTheGenerator) {
  const Zones z = loadZones(kLabZones);
  polyloc::MapLayout layout;
  polyloc::generateMap("lab", &layout);
  ASSERT_EQ(z.doors.size(), layout.doors.size());
  for (const polyloc::DoorInfo& g : layout.doors) {
    const auto i = z.doorIndex(g.name);
    ASSERT_TRUE(i) << g.name;
    const Door& d = z.doors[*i];
    EXPECT_NEAR((d.centre - g.centre.cast<double>()).norm(), 0.0, 1e-6) << g.name;
    EXPECT_NEAR(std::abs(d.along.dot(g.along.cast<double>())), 1.0, 1e-6) << g.name;
    EXPECT_NEAR(d.width, g.width, 1e-6) << g.name;
    EXPECT_EQ(d.closed, g.closed) << g.name;
  }
  // The stairwell's hole lies in the danger zone with the railing's and landing's margin.
  ASSERT_EQ(layout.stairwells.size(), 1u);
  const Eigen::AlignedBox2d hole = layout.stairwells[0].cast<double>();
  const Polygon grown = rect(hole.min().x() - 0.4, hole.min().y() - 0.4, hole.max().x() + 0.4, hole.max().y() + 0.4);
  for (const Vector2d& p : grown) EXPECT_TRUE(z.inDanger(p)) << p.transpose();
  EXPECT_TRUE(pointInPolygon(z.danger[0].polygon, hole.center()));
}

TEST(NavZones, LabDangerCoversEveryDangerTriangle) {
  const Zones z = loadZones(kLabZones);
  const polyloc::Mesh m = polyloc::loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  const int64_t danger = m.findLabel("danger");
  ASSERT_GE(danger, 0);
  size_t triangles = 0;
  for (size_t t = 0; t < m.numTriangles(); ++t) {
    if (m.triangle_label[t] != uint32_t(danger)) continue;
    ++triangles;
    for (uint32_t v : m.triangles[t]) {
      const Vector2d p = m.vertices[v].head<2>().cast<double>();
      EXPECT_TRUE(z.inDanger(p)) << "triangle " << t << " vertex " << p.transpose();
    }
  }
  EXPECT_GT(triangles, 100u);
}

TEST(NavZones, LabGoalsClearOfTheMapByTenCentimetres) {
  const Zones z = loadZones(kLabZones);
  const polyloc::Mesh m = polyloc::loadMesh(std::string(POLYLOC_SOURCE_DIR) + "/maps/lab.obj");
  // The 0.6 x 0.5 m footprint grown by 0.1 m on every side (a little more at the corners), from
  // 6 cm above the floor to 1.2 m: touching nothing means 0.1 m clear of walls and furniture.
  polyloc::RobotSpec grown;
  for (const Vector2d& p : robot(0.8, 0.7)) grown.footprint.push_back(p);
  grown.height = 1.2;
  const polyloc::BodyCollider body(m, grown, 0.06);
  // The check sees furniture: 5 cm closer to the lab 1 bench than 0.1 m is a contact.
  const GoalSpot& bench = z.goals[*z.goalIndex("lab 1 bench")];
  EXPECT_TRUE(body.check(polyloc::Pose::planar(bench.pose.x() - 0.2, bench.pose.y(), bench.pose.z())).hit);

  ASSERT_GE(z.goals.size(), 8u);
  std::map<std::string, int> per_room;
  for (const GoalSpot& g : z.goals) {
    for (const Vector3d& p : {g.pose, approachPose(g)}) {
      const polyloc::BodyContact c = body.check(polyloc::Pose::planar(p.x(), p.y(), p.z()));
      EXPECT_FALSE(c.hit) << g.name << " at " << p.transpose() << " touches '" << c.label << "' at "
                          << c.where.transpose();
      EXPECT_FALSE(z.inDanger(robot(), p)) << g.name;
    }
    const std::string room = z.roomAt(g.pose.head<2>());
    EXPECT_NE(room, "") << g.name;
    ++per_room[room];
  }
  for (const Room& r : z.rooms) EXPECT_GE(per_room[r.name], 1) << r.name;
}

// ------------------------------------------------------------------------------------ rasterising

TEST(NavZones, MarkDangerAndDoorsOnASmallGrid) {
  NavGrid g;
  g.width = 20, g.height = 20, g.resolution = 0.1;  // 2 x 2 m, cell centres at 0.05 + 0.1 k
  g.occupied.assign(g.size(), 0);
  auto cells = [&](const std::vector<uint8_t>& v) {
    std::set<std::pair<size_t, size_t>> out;
    for (size_t i = 0; i < v.size(); ++i)
      if (v[i]) out.insert({i % g.width, i / g.width});
    return out;
  };
  auto block = [](size_t x0, size_t y0, size_t x1, size_t y1) {  // [x0, x1] x [y0, y1]
    std::set<std::pair<size_t, size_t>> out;
    for (size_t y = y0; y <= y1; ++y)
      for (size_t x = x0; x <= x1; ++x) out.insert({x, y});
    return out;
  };

  Zones z;
  // Edges 0.02 m inside the centres at 0.55 and 0.95: centres 0.55..0.95 (cells 5..9) only.
  z.danger.push_back({"a", rect(0.52, 0.52, 0.98, 0.98)});
  NavGrid a = g;
  markDanger(z, a);
  EXPECT_EQ(cells(a.occupied), block(5, 5, 9, 9));
  // Edges 0.02 m beyond centres 0.45: those cells are within half a cell, so they count too.
  z.danger[0].polygon = rect(0.47, 0.47, 0.98, 0.98);
  a = g;
  markDanger(z, a);
  EXPECT_EQ(cells(a.occupied), block(4, 4, 9, 9));
  // A triangle reaching out of the grid: clipped; a zone wholly outside: nothing.
  // Hypotenuse x + y = 0.36: centres with x + y <= 0.4 lie inside or within 0.05 m of it.
  z.danger[0].polygon = {{-1, -1}, {1.36, -1}, {-1, 1.36}};
  z.danger.push_back({"far", rect(5, 5, 6, 6)});
  a = g;
  markDanger(z, a);
  EXPECT_EQ(cells(a.occupied), (std::set<std::pair<size_t, size_t>>{
                                   {0, 0}, {1, 0}, {2, 0}, {3, 0}, {0, 1}, {1, 1}, {2, 1}, {0, 2}, {1, 2}, {0, 3}}));
  EXPECT_TRUE(a.door.empty());

  // Doors: an open one 0.36 m wide in a 0.12 m wall at y = 1 (opening x 1.32..1.68, y 0.94..1.06),
  // a closed one in a wall at x = 0.5 (opening y 1.32..1.68, x 0.44..0.56).
  Zones d;
  d.doors.push_back({"open", {1.5, 1.0}, {1, 0}, 0.36, 0.6, 0.12, false});
  d.doors.push_back({"shut", {0.5, 1.5}, {0, -1}, 0.36, 0.6, 0.12, true});
  NavGrid b = g;
  markDoors(d, b);
  ASSERT_EQ(b.door.size(), b.size());
  EXPECT_EQ(cells(b.door), block(13, 9, 16, 10));
  EXPECT_EQ(cells(b.occupied), block(4, 13, 5, 16));
  EXPECT_TRUE(b.isDoor(*b.cellAt({1.5, 1.0})));
  EXPECT_FALSE(b.isDoor(*b.cellAt({1.5, 1.2})));

  NavGrid bad = g;
  bad.occupied.resize(3);
  EXPECT_NE(thrown([&] { markDanger(z, bad); }).find("occupied has 3 cells"), std::string::npos);
  EXPECT_NE(thrown([&] { markDoors(d, bad); }).find("occupied has 3 cells"), std::string::npos);
}

TEST(NavZones, MarkTheLabOnItsGrid) {
  // The whole lab at 5 cm: the stairwell's cells are occupied and the three lab doors labelled.
  const Zones z = loadZones(kLabZones);
  NavGrid g;
  g.width = 540, g.height = 300, g.resolution = 0.05, g.origin_x = -0.5, g.origin_y = -0.5;
  g.occupied.assign(g.size(), 0);
  markDanger(z, g);
  markDoors(z, g);
  size_t occupied = 0, doors = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    occupied += g.occupied[i];
    doors += g.isDoor(i);
    if (g.occupied[i]) {
      const Vector2d c = g.centre(i);
      EXPECT_TRUE(z.dangerDistance(c) <= 0.025 + 1e-9 || c.x() > 25.9) << c.transpose();
    }
  }
  for (const Door& d : z.doors) {
    const auto cell = g.cellAt(d.centre);
    ASSERT_TRUE(cell);
    EXPECT_EQ(g.isDoor(*cell), !d.closed) << d.name;
    EXPECT_EQ(g.occupied[*cell], d.closed ? 1 : 0) << d.name;
  }
  EXPECT_EQ(doors, 3u * 16u * 4u);  // 0.75 m x 0.15 m: 16 x 4 cell centres on or inside each opening
  EXPECT_TRUE(g.occupied[*g.cellAt({24.7, 6.0})]);
  EXPECT_FALSE(g.occupied[*g.cellAt({23.3, 6.0})]);
  EXPECT_GT(occupied, 50u * 130u);
}

// Random missions (polynav --random and eval nav draw them with this one function): the same
// seed gives the same goals, a goal never follows itself, and fewer than 2 goals is an error.
TEST(NavZones, RandomGoalsAreSeededAndNeverRepeatAGoalAtOnce) {
  polynav::Zones z;
  for (const char* name : {"a", "b", "c"}) z.goals.push_back({name, {double(z.goals.size()), 0, 0}, 0.5});
  const auto first = polynav::randomGoals(z, 200, 7), again = polynav::randomGoals(z, 200, 7);
  const auto other = polynav::randomGoals(z, 200, 8);
  ASSERT_EQ(first.size(), 200u);
  std::map<std::string, int> count;
  bool differs = false;
  for (size_t k = 0; k < first.size(); ++k) {
    EXPECT_EQ(first[k].name, again[k].name);
    differs |= first[k].name != other[k].name;
    if (k) {
      EXPECT_NE(first[k].name, first[k - 1].name) << k;
    }
    ++count[first[k].name];
  }
  EXPECT_TRUE(differs);
  EXPECT_EQ(count.size(), 3u);
  for (const auto& [name, n] : count) EXPECT_GT(n, 40) << name;  // about 67 each
  z.goals.resize(1);
  EXPECT_THROW(polynav::randomGoals(z, 3, 7), polynav::ZonesError);
}

}  // namespace polyloc::t_nav_zones
