// What the filter weighs with (mcl/weighing.hpp): mcl.sensors, mcl.caster. A grid2d filter picks
// the level scanners and tracks on the slice; unknown sensors and unfit choices are config errors.
#include "mcl_fixtures.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/mcl/config_yaml.hpp>
#include <polyloc/mcl/weighing.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_weighing {

using namespace polyloc;
using namespace polyloc::test;


std::vector<std::string> weighedNames(const Rig& rig, const MclConfig& cfg) {
  std::vector<std::string> out;
  const std::vector<uint8_t> on = weighedSensors(rig, cfg);
  for (size_t i = 0; i < rig.size(); ++i)
    if (on[i]) out.push_back(rig.sensors[i].name);
  return out;
}

std::string configError(const std::string& text, const Rig& rig) {
  try {
    ConfigMap m = ConfigMap::parse(text, "w.yaml");
    parseMclConfig(m.map("mcl"), &rig);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}


TEST(MclWeighing, SensorsAndGridPicksLevelScanners) {
  const Rig lisa = rigPreset("lisa");
  MclConfig cfg;
  EXPECT_EQ(weighedNames(lisa, cfg).size(), lisa.size());  // default: every sensor
  cfg.caster = "grid2d";
  const std::vector<std::string> level = weighedNames(lisa, cfg);
  ASSERT_EQ(level.size(), 2u);  // the two S300s at 0.10 m; the URGs are pitched 40 deg, the ToF is a camera
  for (const std::string& n : level) EXPECT_TRUE(lisa.isLevelScanner(size_t(lisa.find(n)))) << n;
  EXPECT_NEAR(weighingSliceHeight(lisa, cfg), lisa.sensors[size_t(lisa.find(level[0]))].mount.z(), 1e-9);
  cfg.caster_height = 0.25;
  EXPECT_DOUBLE_EQ(weighingSliceHeight(lisa, cfg), 0.25);

  MclConfig one;
  one.sensors = {level[1]};
  EXPECT_EQ(weighedNames(lisa, one), std::vector<std::string>{level[1]});
  one.sensors = {"nope"};
  EXPECT_THROW(weighedSensors(lisa, one), std::invalid_argument);
}

TEST(MclWeighing, ConfigErrorsNameTheKey) {
  const Rig lisa = rigPreset("lisa");
  std::string tilted;
  for (size_t i = 0; i < lisa.size(); ++i)
    if (!lisa.isLevelScanner(i)) tilted = lisa.sensors[i].name;
  ASSERT_FALSE(tilted.empty());
  const std::string unknown = configError("mcl:\n  sensors: [s300_front_left, nope]\n", lisa);
  EXPECT_NE(unknown.find("w.yaml:2"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("'nope' is not in rig 'lisa'"), std::string::npos) << unknown;
  const std::string grid = configError("mcl:\n  caster: grid2d\n  sensors: [" + tilted + "]\n", lisa);
  EXPECT_NE(grid.find("level planar scanners only"), std::string::npos) << grid;
  EXPECT_NE(grid.find(tilted), std::string::npos) << grid;
  const std::string backend = configError("mcl:\n  caster: voxels\n", lisa);
  EXPECT_NE(backend.find("grid2d"), std::string::npos) << backend;  // lists the choices
  EXPECT_EQ(configError("mcl:\n  caster: grid2d\n  caster_resolution: 0.02\n", lisa), "");
  ConfigMap m = ConfigMap::parse("mcl:\n  caster: bsp\n  caster_height: 0.2\n", "w.yaml");
  const MclConfig c = parseMclConfig(m.map("mcl"), &lisa);
  EXPECT_EQ(c.caster, "bsp");
  EXPECT_DOUBLE_EQ(c.caster_height, 0.2);
  EXPECT_EQ(makeWeighingCaster(boxRoom(4.f, 3.f, 2.5f, 0.2f), lisa, MclConfig{}, 1), nullptr);  // embree: the caller's
}

// The filter weighs against a 5 cm grid sliced at the scanner's height and still tracks the loop
// of the asymmetric room within a few centimetres (scans come from the exact mesh).
TEST(MclWeighing, Grid2dFilterTracks) {
  const LoopRun r = trackLoopWeighingOn("grid2d");
  EXPECT_EQ(r.weighed_by, "grid2d");
  // Measured 17.9 mm / 0.44 deg (5 cm cells): 1.5x worse fails (was 8 cm / 3 deg).
  EXPECT_LT(r.pos_err, 0.027);
  EXPECT_LT(r.yaw_err_deg, 0.66);
  EXPECT_EQ(r.estimate.status, MclStatus::Tracking);
  EXPECT_GT(r.estimate.updates, 40u);
}

// A sensor left out of mcl.sensors never moves the filter: garbage from it changes nothing.
TEST(MclWeighing, UnlistedSensorIsIgnored) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  Rig rig = scannerRig();
  rig.add(Sensor{"rear", rig.sensors[0].spec, Pose::fromXYZRPY(-0.1, 0, 0.2, 0, 0, M_PI)}, "");
  MclConfig cfg;
  cfg.particles = 500;
  cfg.sensors = {"front"};
  const auto truth = loopTrajectory(40);
  auto run = [&](bool garbage) {
    Localizer loc(caster, mesh, rig, cfg);
    loc.initPose(truth[0], planarCov(0.1, 0.05), 0);
    const std::vector<float> junk(rig.sensors[1].beams().size(), 0.3f);  // a wall 0.3 m behind: false
    for (size_t i = 0; i < truth.size(); ++i) {
      const int64_t t = int64_t(i) * 100'000'000;
      loc.addOdometry(t, truth[i]);
      if (garbage) {
        EXPECT_FALSE(loc.addScan(1, t, junk));
      }
      loc.addScan(0, t, simulateScan(caster, rig.sensors[0], truth[i], 0.01, i));
    }
    return loc.estimate().pose;
  };
  const Pose clean = run(false), dirty = run(true);
  EXPECT_EQ(clean.translation(), dirty.translation());
  EXPECT_LT(posErr(clean, truth.back()), 0.05);
}

}  // namespace polyloc::t_mcl_weighing
