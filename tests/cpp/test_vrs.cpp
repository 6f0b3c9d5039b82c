// Virtual range scans on known geometry: direct scans, the height band, the obstacle memory and
// its filters, danger zones, cone sensors, bad input, the `vrs:` config section.
#include "mcl_fixtures.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/mapgen/builder.hpp>
#include <polyloc/sim/vrs_truth.hpp>
#include <polyloc/vrs/config_yaml.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_vrs {

using namespace polyloc;
using namespace polyloc::test;


// A 360 deg scanner at `z` with `pitch` (down > 0), 0.5 deg resolution, 8 m.
Sensor scanner(const std::string& name, double z, double pitch_deg, double yaw_deg = 0) {
  PlanarScannerSpec spec;
  spec.fov_rad = deg2rad(359.5);
  spec.resolution_rad = deg2rad(0.5);
  spec.range_max = 8.0;
  return Sensor{name, spec, Pose::fromXYZRPY(0, 0, z, 0, deg2rad(pitch_deg), deg2rad(yaw_deg))};
}

RobotSpec smallRobot() {
  RobotSpec r;
  r.footprint = {{0.2, 0.15}, {-0.2, 0.15}, {-0.2, -0.15}, {0.2, -0.15}};
  r.height = 1.2;
  return r;
}

std::vector<float> cast(const RayCaster& c, const Sensor& s, const Pose& base) { return simulateScan(c, s, base, 0.0, 0); }

// Range of the VRS segment that contains direction `deg` (base frame).
float at(const VirtualScan& v, double deg) {
  double a = std::remainder(deg2rad(deg) - v.angle_min, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return v.ranges[size_t(a / v.angle_increment)];
}


TEST(Vrs, DirectScannerGivesTheWalls) {
  const Mesh room = boxRoom(4.f, 3.f, 2.5f, 0.2f);  // walls at x = +-4, y = +-3
  EmbreeCaster caster(room);
  Rig rig;
  rig.add(scanner("s", 0.2, 0), "");
  VirtualRangeScanner vrs(rig, smallRobot(), VrsConfig{});
  const Pose base = Pose::planar(1.0, 0.5, 0.0);
  ASSERT_TRUE(vrs.addFrame(0, 0, base, cast(caster, rig.sensors[0], base)));
  const VirtualScan v = vrs.update(0, base);
  ASSERT_EQ(v.size(), 720u);
  // Segment centres are 0.25 deg off the axes: 3 m / cos(0.25 deg) within a few mm.
  EXPECT_NEAR(at(v, 0), 3.0, 0.01);
  EXPECT_NEAR(at(v, 90), 2.5, 0.01);
  EXPECT_NEAR(at(v, 180), 5.0, 0.01);
  EXPECT_NEAR(at(v, -90), 3.5, 0.01);
  EXPECT_EQ(v.source[0], kVrsDirect);
  EXPECT_EQ(vrs.modeOf(0), VrsMode::Direct);
}

TEST(Vrs, HeightBandFloorAndOverhead) {
  Mesh room = boxRoom(4.f, 3.f, 2.5f, 0.2f);
  mapgen::MeshBuilder b(room);
  b.box({1.5f, -0.5f, 0.0f}, {1.6f, 0.5f, 0.03f}, "cable");  // below floor_clearance
  b.box({-2.0f, -0.5f, 1.5f}, {-1.9f, 0.5f, 1.6f}, "beam");  // above robot_height
  b.box({-0.5f, 1.5f, 0.5f}, {0.5f, 1.6f, 0.9f}, "box");     // in the band
  EmbreeCaster caster(room);
  Rig rig;
  rig.add(scanner("low", 0.02, 0), "");
  rig.add(scanner("high", 1.55, 0), "");
  rig.add(scanner("mid", 0.7, 0), "");
  VirtualRangeScanner vrs(rig, smallRobot(), VrsConfig{});
  const Pose base;
  for (size_t k = 0; k < 3; ++k) vrs.addFrame(k, 0, base, cast(caster, rig.sensors[k], base));
  const VirtualScan v = vrs.update(0, base);
  EXPECT_NEAR(at(v, 0), 4.0, 0.01);    // the cable at 1.5 m is floor; the wall counts
  EXPECT_NEAR(at(v, 180), 4.0, 0.01);  // the beam overhead does not touch the robot
  EXPECT_NEAR(at(v, 90), 1.5, 0.01);   // the box does
}

TEST(Vrs, TiltedScannerTableGoesThroughMemoryAndStays) {
  Mesh room = boxRoom(4.f, 3.f, 2.5f, 0.2f);
  mapgen::MeshBuilder b(room);
  b.box({1.2f, -1.0f, 0.7f}, {2.0f, 1.0f, 0.75f}, "table");  // a top without legs, edge at x = 1.2
  EmbreeCaster caster(room);
  Rig rig;
  rig.add(scanner("horizontal", 0.2, 0), "");
  PlanarScannerSpec fan;  // a forward fan tilted 30 deg down from 1.2 m: meets the table top
  fan.fov_rad = deg2rad(60);
  fan.resolution_rad = deg2rad(0.5);
  fan.range_max = 4.0;
  rig.add(Sensor{"tilted", fan, Pose::fromXYZRPY(0, 0, 1.2, 0, deg2rad(30), 0)}, "");
  VrsConfig cfg;
  VirtualRangeScanner vrs(rig, smallRobot(), cfg);
  EXPECT_EQ(vrs.modeOf(1), VrsMode::Both);
  // The tilted line meets z = 0.75 at 0.78 m ahead of the robot and passes under the top's
  // edge (x = 1.2, z 0.70-0.75) while the robot is behind x = 0.33: the edge shows up from there
  // on, first on the side face, then the line moves onto the top. Drive up to 0.4 m from the edge.
  Pose base;
  int64_t t = 0;
  VirtualScan v;
  bool seen_far = false;
  for (int k = 0; k <= 16; ++k) {
    t += 200'000'000;
    base = Pose::planar(0.05 * k, 0, 0);
    vrs.addFrame(0, t, base, cast(caster, rig.sensors[0], base));
    vrs.addFrame(1, t, base, cast(caster, rig.sensors[1], base));
    v = vrs.update(t, base);
    if (k == 4) seen_far = std::abs(at(v, 0) - 4.0f + float(base.x())) < 0.01;  // wall only, yet
  }
  EXPECT_TRUE(seen_far);
  EXPECT_GT(vrs.memory().size(), 0u);
  EXPECT_NEAR(at(v, 0), 1.2 - 0.8, 0.02);
  // Stand for 30 s, seeing only with the horizontal scanner: the edge does not age.
  for (int k = 0; k < 150; ++k) {
    t += 200'000'000;
    vrs.addFrame(0, t, base, cast(caster, rig.sensors[0], base));
    v = vrs.update(t, base);
  }
  EXPECT_NEAR(at(v, 0), 1.2 - 0.8, 0.02);
  EXPECT_EQ(v.source[360] & kVrsMemory, kVrsMemory);
  // Turning on the spot ages it: after the lifetime (10 s of motion) it is gone.
  for (int k = 0; k < 60; ++k) {
    t += 200'000'000;
    base = Pose::planar(0.8, 0, 0.02 * k);
    v = vrs.update(t, base);
  }
  EXPECT_EQ(vrs.memory().size(), 0u);
}

TEST(Vrs, MemoryFiltersFarBehindAndMoving) {
  const Mesh room = boxRoom(6.f, 6.f, 2.5f, 0.2f);
  EmbreeCaster caster(room);
  Rig rig;
  rig.add(scanner("horizontal", 0.2, 0), "");
  rig.add(scanner("tof", 0.5, 0), "");
  VrsConfig cfg;
  cfg.sources = {{"horizontal", VrsMode::Direct}, {"tof", VrsMode::Memory}};
  VirtualRangeScanner vrs(rig, smallRobot(), cfg);
  const Pose base;
  // Points: far (5 m), behind the direct wall, and on a tracked person at (1, 1).
  const std::vector<Eigen::Vector3f> pts = {{5.0f, 0.f, 0.5f}, {1.0f, 1.0f, 0.5f}, {1.1f, 0.95f, 0.8f}, {-1.0f, 0.f, 0.5f}};
  const MovingObject person{{1.0, 1.0}, {0.0, 0.0}, Eigen::Matrix2d::Identity() * 0.01, 0};
  vrs.setMovingObjects(std::span(&person, 1));
  vrs.addFrame(0, 0, base, cast(caster, rig.sensors[0], base));
  vrs.addPoints(1, 0, base, pts);
  vrs.update(0, base);
  EXPECT_EQ(vrs.counters().memory_inserted, 0u);  // candidates wait memory.delay for the tracks
  vrs.update(1'100'000'000, base);
  EXPECT_EQ(vrs.counters().memory_far, 1u);
  EXPECT_EQ(vrs.counters().memory_moving, 2u);
  EXPECT_EQ(vrs.counters().memory_inserted, 1u);  // the point at (-1, 0): nearer than the wall
  // A point behind what the horizontal scanner sees (wall at 6 m, within max_distance? no: use
  // a box) is not remembered: the direct sources already cover it.
  Mesh box_room = boxRoom(6.f, 6.f, 2.5f, 0.2f);
  mapgen::MeshBuilder(box_room).box({0.0f, -2.1f, 0.f}, {0.2f, -2.0f, 1.f}, "box");
  EmbreeCaster c2(box_room);
  VirtualRangeScanner v2(rig, smallRobot(), cfg);
  v2.addFrame(0, 0, base, cast(c2, rig.sensors[0], base));
  const std::vector<Eigen::Vector3f> behind = {{0.1f, -2.5f, 0.5f}};
  v2.addPoints(1, 0, base, behind);
  v2.update(0, base);
  EXPECT_EQ(v2.counters().memory_behind, 1u);
  EXPECT_EQ(v2.memory().size(), 0u);
}

TEST(Vrs, DangerZonesAreAlwaysThere) {
  VrsConfig cfg;
  cfg.danger_zones = {{{2.0, -0.5}, {3.0, -0.5}, {3.0, 0.5}, {2.0, 0.5}}};
  Mesh map = boxRoom(6.f, 6.f, 2.5f, 0.2f);
  mapgen::MeshBuilder(map).box({-3.0f, -3.0f, -0.5f}, {-2.0f, -2.0f, 0.f}, "danger");  // a pit, by label
  Rig rig;
  rig.add(scanner("s", 0.2, 0), "");
  VirtualRangeScanner vrs(rig, smallRobot(), cfg, &map);
  EXPECT_FALSE(vrs.dangerZones().empty());
  for (double x : {0.0, 0.5, 1.0}) {
    const Pose base = Pose::planar(x, 0, 0);
    const VirtualScan v = vrs.update(int64_t(x * 1e9), base);
    // No sensor frame at all: still there, conservative by at most one raster cell.
    EXPECT_LE(at(v, 0), 2.0 - x + 1e-3) << x;
    EXPECT_GE(at(v, 0), 2.0 - x - cfg.danger_resolution - 1e-3) << x;
    EXPECT_EQ(v.source[360], kVrsDanger);
    // The pit's corner (-2, -2) seen from (x, 0).
    const double d = std::hypot(-2.0 - x, -2.0), a = rad2deg(std::atan2(-2.0, -2.0 - x));
    EXPECT_NEAR(at(v, a), d, 0.08) << x;
  }
}

TEST(Vrs, ConeSensorAndSelfPoints) {
  VrsConfig cfg;
  VrsCone cone;
  cone.name = "sonar";
  cone.position = {0.2, 0, 0.3};
  cone.half_angle = deg2rad(15);
  cfg.cones = {cone};
  Rig rig;
  rig.add(scanner("s", 0.2, 0), "");
  VirtualRangeScanner vrs(rig, smallRobot(), cfg);
  const Pose base;
  ASSERT_TRUE(vrs.addCone(0, 0, base, 1.0f));
  // A frame whose returns lie on the robot's own body (range 0.1 m) is ignored.
  std::vector<float> self(rig.sensors[0].beams().size(), 0.1f);
  vrs.addFrame(0, 0, base, self);
  const VirtualScan v = vrs.update(0, base);
  // The cap at 1 m from (0.2, 0): ahead, its nearest points are on the rim, 15 deg off the axis
  // up and down: 0.2 + cos(15 deg); every segment across the cone's width is filled.
  EXPECT_NEAR(at(v, 0), 0.2 + std::cos(deg2rad(15)), 0.005);
  for (double a = -12; a <= 12; a += 0.5) EXPECT_TRUE(std::isfinite(at(v, a))) << a;
  EXPECT_FALSE(std::isfinite(at(v, 20)));
  EXPECT_FALSE(std::isfinite(at(v, 90)));  // nothing else: the self returns were dropped
  EXPECT_FALSE(vrs.addCone(3, 0, base, 1.0f));
}

TEST(Vrs, BadInputIsRejectedAndCounted) {
  Rig rig;
  rig.add(scanner("s", 0.2, 0), "");
  VirtualRangeScanner vrs(rig, smallRobot(), VrsConfig{});
  const Pose base;
  EXPECT_FALSE(vrs.addFrame(0, 0, base, std::vector<float>(3, 1.f)));  // wrong size
  EXPECT_FALSE(vrs.addFrame(5, 0, base, std::vector<float>(720, 1.f)));  // no such sensor
  const Pose nan = Pose::planar(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  EXPECT_FALSE(vrs.addFrame(0, 0, nan, std::vector<float>(rig.sensors[0].beams().size(), 1.f)));
  std::vector<float> garbage(rig.sensors[0].beams().size(), std::numeric_limits<float>::quiet_NaN());
  garbage[3] = -1.f, garbage[4] = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(vrs.addFrame(0, 0, base, garbage));  // accepted, no point from it
  const VirtualScan v = vrs.update(0, base);
  for (float r : v.ranges) EXPECT_FALSE(std::isfinite(r));
  EXPECT_EQ(vrs.counters().frames_rejected, 3u);
  const VirtualScan w = vrs.update(1, nan);  // an update at a non-finite pose: empty, counted
  EXPECT_EQ(vrs.counters().frames_rejected, 4u);
  EXPECT_EQ(w.size(), 720u);
  VrsConfig bad;
  bad.sources = {{"nope", VrsMode::Direct}};
  EXPECT_THROW(VirtualRangeScanner(rig, smallRobot(), bad), std::invalid_argument);
}

TEST(VrsConfigYaml, KeysDefaultsAndErrors) {
  ConfigMap m = ConfigMap::parse(
      "vrs:\n  resolution: 1\n  range_max: 5\n  sources: [{sensor: a, mode: memory}]\n"
      "  memory: {lifetime: 4, max_distance: 2}\n  danger_zones: [[[0, 0], [1, 0], [1, 1]]]\n",
      "t.yaml");
  const VrsConfig c = parseVrsConfig(m.map("vrs"), 1.5);
  EXPECT_NEAR(c.resolution, deg2rad(1), 1e-12);
  EXPECT_DOUBLE_EQ(c.range_max, 5);
  EXPECT_DOUBLE_EQ(c.robot_height, 1.5);
  ASSERT_EQ(c.sources.size(), 1u);
  EXPECT_EQ(c.sources[0].mode, VrsMode::Memory);
  EXPECT_DOUBLE_EQ(c.memory.lifetime, 4);
  EXPECT_DOUBLE_EQ(c.memory.resolution, ObstacleMemoryConfig{}.resolution);
  ASSERT_EQ(c.danger_zones.size(), 1u);
  auto error = [](const std::string& text) {
    try {
      ConfigMap mm = ConfigMap::parse(text, "t.yaml");
      parseVrsConfig(mm.map("vrs"), 1.2);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("vrs:\n  resolutoin: 1\n").find("resolutoin"), std::string::npos);
  EXPECT_NE(error("vrs:\n  sources: [{sensor: a, mode: sideways}]\n").find("sideways"), std::string::npos);
  EXPECT_NE(error("vrs:\n  danger_zones: [[[0, 0], [1, 0]]]\n").find("3 corners"), std::string::npos);
  EXPECT_NE(error("vrs:\n  memory: {max_distance: 50}\n").find("max_distance"), std::string::npos);
  EXPECT_NE(error("vrs:\n  resolution: 1\n").find("t.yaml"), std::string::npos - 1);
}

TEST(VrsTruth, NearestSurfaceInTheBandPerSegment) {
  Mesh room = boxRoom(4.f, 3.f, 2.5f, 0.2f);
  mapgen::MeshBuilder b(room);
  b.box({1.2f, -1.0f, 0.715f}, {2.0f, 1.0f, 0.75f}, "table");  // a 3.5 cm top: found between heights
  b.box({-2.0f, -0.5f, 1.5f}, {-1.9f, 0.5f, 1.6f}, "beam");   // above robot_height: not there
  EmbreeCaster caster(room);
  People people({});
  VrsConfig cfg;
  const std::vector<float> r = trueVirtualScan(caster, people.scene(0, {0, 0}), Pose::planar(0.2, 0, 0), cfg);
  ASSERT_EQ(r.size(), 720u);
  EXPECT_NEAR(r[360], 1.0, 0.005);   // ahead: the table edge
  EXPECT_NEAR(r[0], 4.2, 0.005);     // behind: the wall, not the beam
  EXPECT_NEAR(r[540], 3.0, 0.005);   // left
  cfg.range_max = 2.0;
  EXPECT_FALSE(std::isfinite(trueVirtualScan(caster, people.scene(0, {0, 0}), Pose::planar(0.2, 0, 0), cfg)[0]));
}

}  // namespace polyloc::t_vrs
