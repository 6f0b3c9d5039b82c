// A simulated world that differs from the map (sim/world.hpp) and sensor errors that are not
// the beam model's own (per-beam bias, angular jitter, mixed pixels): each change does what
// docs/simulation.md says, measured in the closed box room of fixtures.hpp.
#include "sim_fixtures.hpp"
#include "temp_dir.hpp"

#include <polyloc/mapgen/builder.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/sim/chairs.hpp>
#include <polyloc/sim/world.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_world {

using namespace polyloc;


Mesh room() { return test::boxRoom(4.f, 3.f, 2.5f, 0.2f); }

// Room with a table (two solids that touch: top and one leg) and a cabinet.
Mesh furnished() {
  Mesh m = room();
  mapgen::MeshBuilder b(m);
  b.box({1.0f, 1.0f, 0.7f}, {2.0f, 1.8f, 0.75f}, "table");
  b.box({1.45f, 1.35f, 0.f}, {1.55f, 1.45f, 0.7f}, "table");
  b.box({-3.0f, -2.5f, 0.f}, {-2.4f, -1.9f, 1.8f}, "cabinet");
  return m;
}

float castOne(const Mesh& m, Eigen::Vector3f o, Eigen::Vector3f d, uint32_t* label = nullptr) {
  const EmbreeCaster caster(m);
  d.normalize();
  float r = 0;
  uint32_t l = 0;
  caster.castRays({&o.x(), &o.y(), &o.z(), &d.x(), &d.y(), &d.z(), nullptr, nullptr, 1}, {&r, nullptr, &l});
  if (label) *label = l;
  return r;
}

std::vector<SimFrame> frames(Scenario s, const Mesh& map) {
  Simulator sim(std::move(s), map);
  std::vector<SimFrame> fs;
  test::CaptureWriter out;
  SimHooks hooks;
  hooks.on_frame = [&](const SimFrame& f) { fs.push_back(f); };
  sim.run(out, hooks);
  return fs;
}

// A scanner at the origin with every noise off but the one under test.
Scenario quietScanner(const Sensor& sensor, const std::string& preset, double duration) {
  Scenario s = test::roomScenario(sensor, preset, duration);
  SensorNoise& n = s.noise.sensors[0];
  n.sigma = n.sigma_slope = n.sigma_rel = 0, n.dropout = n.max_range = 0, n.flying_pixel = 0;
  return s;
}


TEST(SimWorld, RemovedObjectsAreGoneAndAMissingOneIsAnErrorNamingItsEntry) {
  const Mesh map = furnished();
  WorldSpec spec;
  spec.remove.push_back({"table", {1.5, 1.4}, "s.yaml:7"});
  WorldChanges ch;
  const Mesh w = buildWorld(map, spec, 1, {}, &ch);
  EXPECT_EQ(ch.removed, 1u);
  EXPECT_EQ(w.numTriangles(), map.numTriangles() - 24);  // top and leg: one object, 2 x 12 triangles
  EXPECT_TRUE(findObjects(w, "table").empty());
  // A ray down onto the table top now reaches the floor.
  EXPECT_NEAR(castOne(map, {1.5f, 1.1f, 2.f}, {0, 0, -1}), 1.25f, 1e-4);
  EXPECT_NEAR(castOne(w, {1.5f, 1.1f, 2.f}, {0, 0, -1}), 2.0f, 1e-4);

  spec.remove[0].at = {0, 0};
  try {
    buildWorld(map, spec, 1, {});
    FAIL() << "no table near (0, 0)";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml:7: no 'table' object within 0.6 m"), std::string::npos) << e.what();
  }
}

TEST(SimWorld, AddedBoxesStandWhereGivenTurnedAboutTheirCentre) {
  const Mesh map = room();
  WorldSpec spec;
  spec.add.push_back({{-1.0, -0.5, 0.0}, {1.0, 0.5, 1.0}, M_PI / 2, "cabinet"});
  const Mesh w = buildWorld(map, spec, 1, {});
  ASSERT_EQ(w.numTriangles(), map.numTriangles() + 12);
  uint32_t label = 0;
  // 2 m along x and 1 m along y before the turn; turned by 90 deg: x in [-0.5, 0.5], y in [-1, 1].
  EXPECT_NEAR(castOne(w, {0.f, -2.5f, 0.5f}, {0, 1, 0}, &label), 1.5f, 1e-4);
  EXPECT_EQ(w.label_names[label], "cabinet");
  EXPECT_NEAR(castOne(w, {-3.f, 0.f, 0.5f}, {1, 0, 0}), 2.5f, 1e-4);
}

TEST(SimWorld, WallSolidsShiftByAtMostTheOffsetEachItsOwnWay) {
  const Mesh map = room();
  WorldSpec spec;
  spec.wall_offset = 0.03;
  WorldChanges ch;
  const Mesh w = buildWorld(map, spec, 5, {}, &ch);
  const std::vector<MeshObject> before = findObjects(map, "wall", false), after = findObjects(w, "wall", false);
  EXPECT_EQ(ch.shifted, before.size());  // every wall solid of the room
  EXPECT_GE(before.size(), 4u);
  ASSERT_EQ(before.size(), after.size());
  double largest = 0;
  std::vector<Eigen::Vector3f> shifts;
  for (size_t i = 0; i < before.size(); ++i) {
    const Eigen::Vector3f s = after[i].bounds.center() - before[i].bounds.center();
    EXPECT_LE(s.head<2>().norm(), 0.03 + 1e-5);
    EXPECT_NEAR(s.z(), 0.f, 1e-6);
    largest = std::max<double>(largest, s.norm());
    shifts.push_back(s);
  }
  EXPECT_GT(largest, 0.005);
  EXPECT_GT((shifts[0] - shifts[1]).norm(), 1e-4);  // not one shift of the whole building
  // A ray to the east wall measures the shifted wall, within the offset of 4 m.
  const float r = castOne(w, {0.f, 0.f, 1.f}, {1, 0, 0});
  EXPECT_NEAR(r, 4.0f, 0.0301f);
  // Same seed, same world; floor and ceiling untouched.
  EXPECT_EQ(buildWorld(map, spec, 5, {}).vertices, w.vertices);
  EXPECT_NEAR(castOne(w, {0.f, 0.f, 1.f}, {0, 0, -1}), 1.0f, 1e-5);
}

TEST(SimWorld, SubdivisionKeepsTheSurfaces) {
  const Mesh map = furnished();
  WorldSpec spec;
  spec.subdivide = 2;
  const Mesh w = buildWorld(map, spec, 1, {});
  EXPECT_EQ(w.numTriangles(), map.numTriangles() * 16);
  const EmbreeCaster a(map), b(w);
  BeamSet beams;
  for (int i = 0; i < 720; ++i) beams.push(float(std::cos(i * M_PI / 360)), float(std::sin(i * M_PI / 360)), 0.f);
  std::vector<float> ra(beams.size()), rb(beams.size());
  const std::vector<Pose> poses{Pose::fromXYZRPY(0.3, -0.2, 0.72, 0, 0.1, 0.4)};
  a.castScans(poses, beams, {ra.data()});
  b.castScans(poses, beams, {rb.data()});
  for (size_t i = 0; i < ra.size(); ++i) ASSERT_NEAR(ra[i], rb[i], 1e-4) << "beam " << i;
}

TEST(SimWorld, ClutterStandsOnFreeFloorAwayFromTheRoute) {
  const Mesh map = furnished();
  WorldSpec spec;
  spec.clutter.count = 12;
  spec.clutter.route_clearance = 0.5;
  const std::vector<Eigen::Vector2d> route{{-3.5, 0.0}, {3.5, 0.0}};
  WorldChanges ch;
  const Mesh w = buildWorld(map, spec, 3, route, &ch);
  ASSERT_EQ(ch.clutter, 12u);
  const std::vector<MeshObject> boxes = findObjects(w, "clutter", false);
  ASSERT_EQ(boxes.size(), 12u);
  for (const MeshObject& o : boxes) {
    EXPECT_NEAR(o.bounds.min().z(), 0.f, 1e-5);  // on the floor, not on the table or the cabinet
    const Eigen::AlignedBox3f& bb = o.bounds;
    EXPECT_GE(std::min(std::abs(bb.min().y()), std::abs(bb.max().y())), 0.5 - 1e-4) << "too close to the route";
    EXPECT_FALSE(bb.min().y() < 0 && bb.max().y() > 0) << "on the route";
    EXPECT_LE(bb.max().z(), 1.0f + 1e-5);
  }
  // No free floor: an error saying so.
  spec.clutter.count = 500;
  spec.clutter.size_min = spec.clutter.size_max = 3.0;
  EXPECT_THROW(buildWorld(map, spec, 3, route), std::runtime_error);
}

TEST(SimWorld, TheSensorsSeeTheWorldNotTheMap) {
  const Mesh map = room();
  Scenario s = quietScanner({"s300", sickS300(), Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)}, "sick_s300", 0.5);
  s.world.add.push_back({{1.0, -0.5, 0.0}, {1.5, 0.5, 1.0}, 0.0, "cabinet"});
  Simulator sim(s, map);
  EXPECT_EQ(sim.worldChanges().added, 1u);
  const std::vector<SimFrame> fs = frames(s, map);
  ASSERT_FALSE(fs.empty());
  const BeamSet beams = s.config.rig.sensors[0].beams();
  size_t ahead = 0;
  for (size_t b = 0; b < beams.size(); ++b)
    if (std::abs(std::atan2(beams.dy[b], beams.dx[b])) < 0.2) {
      EXPECT_NEAR(fs[0].measured[b] * beams.dx[b], 1.0f, 1e-3);  // the box, not the wall at 4 m
      ++ahead;
    }
  EXPECT_GT(ahead, 10u);
}

TEST(SimSensorErrors, BeamBiasIsFixedPerBeamAndHasItsSpread) {
  const Mesh map = room();
  Scenario s = quietScanner({"lms", sickLMS200(), Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)}, "sick_lms200", 1.0);
  s.noise.sensors[0].beam_bias = 0.02;
  const std::vector<SimFrame> fs = frames(s, map);
  ASSERT_GE(fs.size(), 10u);
  double sum2 = 0;
  size_t n = 0;
  for (size_t b = 0; b < fs[0].exact.size(); ++b) {
    if (!std::isfinite(fs[0].exact[b])) continue;
    const double e0 = fs[0].measured[b] - fs[0].exact[b];
    for (const SimFrame& f : fs) ASSERT_NEAR(f.measured[b] - f.exact[b], e0, 1e-5) << "beam " << b << " frame " << f.index;
    sum2 += e0 * e0, ++n;
  }
  ASSERT_GT(n, 300u);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.004);  // 361 draws: the spread within 20 %
}

TEST(SimSensorErrors, AngularJitterTurnsTheCastBeamByItsSpread) {
  // Facing the east wall (x = 4) head on: a beam at nominal angle a measures 4 / cos(a + jitter),
  // so the jitter can be read back from each range.
  const Mesh map = room();
  Scenario s = quietScanner({"lms", sickLMS200(), Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)}, "sick_lms200", 1.0);
  const double sigma = deg2rad(0.5);
  s.noise.sensors[0].angle_jitter = sigma;
  const std::vector<SimFrame> fs = frames(s, map);
  const BeamSet beams = s.config.rig.sensors[0].beams();
  double sum = 0, sum2 = 0;
  size_t n = 0;
  for (const SimFrame& f : fs)
    for (size_t b = 0; b < beams.size(); ++b) {
      const double a = std::atan2(beams.dy[b], beams.dx[b]);
      if (std::abs(a) < deg2rad(20) || std::abs(a) > deg2rad(30)) continue;  // east wall, oblique enough to read
      const double turned = std::acos(std::min(1.0, 4.0 / f.measured[b]));
      const double jitter = (a > 0 ? turned - a : -turned - a);
      sum += jitter, sum2 += jitter * jitter, ++n;
    }
  ASSERT_GT(n, 200u);
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.2 * sigma);
  EXPECT_NEAR(sd, sigma, 0.2 * sigma);
}

TEST(SimSensorErrors, MixedPixelsAtDepthStepsLieBetweenForeAndBackground) {
  // A pillar 1.5 m ahead in front of the wall at 4 m: beams next to its edges mix both.
  Mesh map = room();
  mapgen::MeshBuilder(map).box({1.5f, -0.3f, 0.f}, {1.9f, 0.3f, 2.5f}, "cabinet");
  Scenario s = quietScanner({"lms", sickLMS200(), Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)}, "sick_lms200", 1.0);
  s.noise.sensors[0].flying_pixel = 1.0;
  size_t mixed = 0, elsewhere = 0;
  for (const SimFrame& f : frames(s, map))
    for (size_t b = 0; b < f.exact.size(); ++b) {
      const bool step = (b > 0 && std::abs(f.exact[b - 1] - f.exact[b]) > 0.2f) ||
                        (b + 1 < f.exact.size() && std::abs(f.exact[b + 1] - f.exact[b]) > 0.2f);
      if (!(f.artefacts[b] & kArtefactFlyingPixel)) {
        EXPECT_FALSE(step) << "beam " << b << " at a step was not mixed";
        continue;
      }
      if (!step) ++elsewhere;
      float lo = f.exact[b], hi = f.exact[b];
      for (size_t k : {b - 1, b + 1})
        if (k < f.exact.size()) lo = std::min(lo, f.exact[k]), hi = std::max(hi, f.exact[k]);
      EXPECT_GT(f.measured[b], lo);
      EXPECT_LT(f.measured[b], hi);
      ++mixed;
    }
  EXPECT_EQ(elsewhere, 0u);
  EXPECT_GE(mixed, 4u);  // two edges, a beam on each side of each
}

TEST(SimWorldYaml, ADerivedScenarioKeepsItsBaseAndReplacesWholeSections) {
  const std::string dir = std::string(POLYLOC_SOURCE_DIR) + "/maps/scenarios/";
  const Scenario base = loadScenario(dir + "lab_tour.yaml");
  const Scenario changed = loadScenario(dir + "lab_tour_changed.yaml");
  EXPECT_EQ(changed.route.waypoints.size(), base.route.waypoints.size());
  EXPECT_EQ(changed.people.size(), base.people.size());
  EXPECT_EQ(changed.chairs.moves.size(), base.chairs.moves.size());
  EXPECT_EQ(changed.seed, base.seed);
  EXPECT_TRUE(base.world.empty());
  EXPECT_DOUBLE_EQ(changed.world.wall_offset, 0.03);
  EXPECT_EQ(changed.world.remove.size(), 2u);
  EXPECT_EQ(changed.world.add.size(), 2u);
  EXPECT_EQ(changed.world.clutter.count, 15);
  EXPECT_EQ(changed.world.subdivide, 2);
  const int s300 = changed.config.rig.find("s300_front_left");
  ASSERT_GE(s300, 0);
  EXPECT_DOUBLE_EQ(changed.noise.sensors[s300].beam_bias, 0.01);
  EXPECT_NEAR(changed.noise.sensors[s300].angle_jitter, deg2rad(0.1), 1e-12);
  EXPECT_DOUBLE_EQ(changed.noise.sensors[s300].sigma, base.noise.sensors[s300].sigma);  // the preset's default kept
}

TEST(SimWorldYaml, BadWorldsAreErrorsNamingFileLineAndKey) {
  test::TempDir dir;
  const std::string base = std::string(POLYLOC_SOURCE_DIR) + "/maps/scenarios/lab_tour.yaml";
  const auto expectError = [&](const std::string& body, const std::string& part) {
    const std::string file = dir.write("s.yaml", "base: " + base + "\n" + body);
    try {
      loadScenario(file);
      ADD_FAILURE() << "no error for: " << body;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError("world: {add: [{box: [0, 0, 0, 1, 1]}]}\n", "s.yaml:2");
  expectError("world: {add: [{box: [1, 0, 0, 0, 1, 1]}]}\n", "x0 < x1");
  expectError("world: {subdivide: 9}\n", "subdivide");
  expectError("world: {wall_ofset: 0.03}\n", "wall_ofset");
  expectError("world: {clutter: {count: 3, size: [0.5, 0.1]}}\n", "min <= max");
  expectError("noise: {sensors: {sick_s300: {angle_jitter: 30}}}\n", "angle_jitter");
  const std::string loop = dir.write("loop.yaml", "base: loop.yaml\n");
  EXPECT_THROW(loadScenario(loop), ConfigError);
}

}  // namespace polyloc::t_sim_world
