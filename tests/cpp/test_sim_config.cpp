// YAML configuration of the simulator: the checked reader (config/yaml), robot, rig, polyloc
// configuration and scenario files; the bundled files load and match the built-in presets.
#include "temp_dir.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/config/yaml.hpp>
#include <polyloc/sensors/rig.hpp>
#include <polyloc/sim/scenario.hpp>

#include <gtest/gtest.h>

#include <filesystem>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_config {

using namespace polyloc;


const std::string kSource = POLYLOC_SOURCE_DIR;

// The message of the ConfigError that `f` throws ("" if none).
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// A scenario file next to a copy of the lab config (so relative paths resolve into maps/).
std::string scenarioText(const std::string& extra) {
  return "config: " + kSource + "/maps/config/lab.yaml\n"
         "route:\n"
         "  waypoints: [[1, 1.75], [3, 1.75]]\n" + extra;
}


TEST(SimConfig, ReaderValuesAndUnits) {
  ConfigMap m = ConfigMap::parse("a: 1.5\nb: 90\nc: 0.5 rad\nd: yes\ne: [1, 2]\nf: {g: 3}\n", "t.yaml");
  EXPECT_EQ(m.getDouble("a", 0), 1.5);
  EXPECT_NEAR(m.getAngle("b", 0), M_PI / 2, 1e-15);
  EXPECT_EQ(m.getAngle("c", 0), 0.5);
  EXPECT_TRUE(m.getBool("d", false));
  EXPECT_EQ(m.value("e").asDoubles(2), (std::vector<double>{1, 2}));
  ConfigMap f = m.map("f");
  EXPECT_EQ(f.getInt("g", 0), 3);
  EXPECT_EQ(m.getDouble("missing", 7), 7);
  EXPECT_NO_THROW(f.finish());
  EXPECT_NO_THROW(m.finish());
  EXPECT_EQ(m.map("absent").getDouble("x", 2), 2);  // an absent section reads as empty
}

TEST(SimConfig, ReaderErrorsNameFileLineAndKey) {
  {
    ConfigMap m = ConfigMap::parse("a: 1\nrobot:\n  height: tall\n", "x.yaml");
    ConfigMap r = m.map("robot");
    const std::string e = errorOf([&] { r.getDouble("height", 1); });
    EXPECT_NE(e.find("x.yaml:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("robot.height"), std::string::npos) << e;
    EXPECT_NE(e.find("expected a number"), std::string::npos) << e;
  }
  {
    ConfigMap m = ConfigMap::parse("alpha: 1\nbeta: 2\n", "y.yaml");
    m.getDouble("alpha", 0);
    const std::string e = errorOf([&] { m.finish(); });
    EXPECT_NE(e.find("y.yaml:2:"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key 'beta'"), std::string::npos) << e;
  }
  EXPECT_NE(errorOf([] { ConfigMap::parse("a: [1, 2\n", "z.yaml"); }).find("z.yaml:"), std::string::npos);
  EXPECT_NE(errorOf([] { ConfigMap::parse("a: 1\n", "q.yaml").getChoice("a", "x", {"x", "y"}); }).find("one of x, y"),
            std::string::npos);
  EXPECT_NE(errorOf([] { ConfigMap::parse("a: 2\n", "q.yaml").getDouble("a", 0, 0, 1); }).find("must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(errorOf([] { ConfigMap::parse("a: 3 grad\n", "q.yaml").getAngle("a", 0); }).find("q.yaml:1:4: a:"),
            std::string::npos);
  EXPECT_NE(errorOf([] { ConfigMap::load("/nonexistent/c.yaml"); }).find("/nonexistent/c.yaml"), std::string::npos);
}

TEST(SimConfig, RigFilesMatchPresets) {
  for (const std::string& name : rigPresetNames()) {
    const Rig file = loadRig(kSource + "/maps/rigs/" + name + ".yaml");
    const Rig preset = rigPreset(name);
    EXPECT_EQ(file.name, name);
    ASSERT_EQ(file.size(), preset.size()) << name;
    for (size_t i = 0; i < file.size(); ++i) {
      EXPECT_EQ(file.sensors[i].name, preset.sensors[i].name);
      EXPECT_EQ(file.presets[i], preset.presets[i]);
      EXPECT_EQ(file.sensors[i].spec.index(), preset.sensors[i].spec.index());
      EXPECT_TRUE(file.sensors[i].mount.isApprox(preset.sensors[i].mount, 1e-12)) << file.sensors[i].name;
    }
  }
  // lisa: the two S300 together see all around (270 deg each, facing diagonally outwards).
  const Rig lisa = rigPreset("lisa");
  EXPECT_EQ(lisa.size(), 7u);
  EXPECT_NEAR(angleDiff(lisa.sensors[0].mount.yaw(), lisa.sensors[1].mount.yaw()), M_PI, 1e-12);
  for (int i = 2; i < 6; ++i) EXPECT_NEAR(lisa.sensors[i].mount.pitch(), deg2rad(40), 1e-12);
  EXPECT_THROW(rigPreset("nope"), std::invalid_argument);
}

TEST(SimConfig, RigYamlOverridesAndErrors) {
  ConfigMap m = ConfigMap::parse(
      "name: r\nsensors:\n"
      "  - name: a\n    preset: sick_lms200\n    mount: {x: 1, yaw: 0.5 rad}\n    spec: {range_max: 20, fov: 90}\n"
      "  - name: cam\n    preset: pmd_o3d100\n    spec: {width: 32, hfov: 60}\n",
      "rig.yaml");
  const Rig r = parseRig(m);
  ASSERT_EQ(r.size(), 2u);
  const auto& lms = std::get<PlanarScannerSpec>(r.sensors[0].spec);
  EXPECT_EQ(lms.range_max, 20);
  EXPECT_NEAR(lms.fov_rad, M_PI / 2, 1e-12);
  EXPECT_NEAR(r.sensors[0].mount.yaw(), 0.5, 1e-12);
  EXPECT_EQ(r.sensors[0].mount.x(), 1);
  EXPECT_EQ(std::get<DepthCameraSpec>(r.sensors[1].spec).width, 32);
  auto err = [](const std::string& text) { return errorOf([&] { parseRig(ConfigMap::parse(text, "r.yaml")); }); };
  EXPECT_NE(err("sensors:\n  - {name: a, preset: laser9000}\n").find("unknown sensor preset"), std::string::npos);
  EXPECT_NE(err("sensors:\n  - {name: a, preset: sick_s300, mount: {z: 1, yaw: 1, pich: 3}}\n").find("unknown key 'sensors[0].mount.pich'"),
            std::string::npos);
  EXPECT_NE(err("sensors:\n  - {name: a, preset: sick_s300}\n  - {name: a, preset: sick_s300}\n").find("two sensors"),
            std::string::npos);
  EXPECT_NE(err("sensors:\n  - {name: a, preset: sick_s300, spec: {width: 3}}\n").find("unknown key"), std::string::npos);
  EXPECT_NE(err("sensors:\n  - {name: a b, preset: sick_s300}\n").find("r.yaml:2:"), std::string::npos);
}

TEST(SimConfig, BundledConfigsAndScenariosLoad) {
  const PolylocConfig lab = loadConfig(kSource + "/maps/config/lab.yaml");
  EXPECT_TRUE(std::filesystem::exists(lab.map.file));
  EXPECT_EQ(lab.rig.name, "lisa");
  EXPECT_EQ(lab.robot.footprint.size(), 4u);
  EXPECT_EQ(lab.robot.kinematics, Kinematics::Differential);
  const PolylocConfig office = loadConfig(kSource + "/maps/config/office.yaml");
  EXPECT_EQ(office.rig.name, "taser");
  for (const char* name : {"lab_tour", "office_patrol", "office_loop", "ramp_6dof", "crowd"}) {
    const Scenario s = loadScenario(kSource + "/maps/scenarios/" + name + ".yaml");
    EXPECT_FALSE(s.route.waypoints.empty()) << name;
    EXPECT_EQ(s.noise.sensors.size(), s.config.rig.size()) << name;
  }
  const Scenario tour = loadScenario(kSource + "/maps/scenarios/lab_tour.yaml");
  EXPECT_GE(tour.duration, 120.0);
  EXPECT_EQ(tour.people.size(), 3u);
  EXPECT_EQ(tour.chairs.moves.size(), 2u);
  EXPECT_EQ(tour.start_time_ns, 1700000000LL * 1000000000LL);
}

TEST(SimConfig, TheRobotIsStatedOnce) {
  // robot.kinematics is the motion model's drive: an omni robot's filter moved its particles as a
  // differential drive unless mcl.motion.drive said omni a second time.
  test::TempDir dir;
  const std::string map = kSource + "/maps/lab.obj";
  const std::string omni = dir.write("omni.yaml", "map: " + map + "\nrig: lisa\nrobot: {radius: 0.3, kinematics: omni}\n"
                                                  "mcl: {particles: 500}\n");
  EXPECT_TRUE(loadConfig(omni).mcl.motion.omni);
  EXPECT_FALSE(loadConfig(kSource + "/maps/config/lab.yaml").mcl.motion.omni);
  // Stated twice and differently: an error at the second statement.
  const std::string both = dir.write("both.yaml", "map: " + map + "\nrig: lisa\nrobot: {radius: 0.3, kinematics: omni}\n"
                                                  "mcl:\n  motion: {drive: differential}\n");
  const std::string e = errorOf([&] { loadConfig(both); });
  EXPECT_NE(e.find(both + ":5:"), std::string::npos) << e;
  EXPECT_NE(e.find("mcl.motion.drive: says differential but robot.kinematics is omni"), std::string::npos) << e;
  // A scenario that replaces its config's robot: the clearance, the drive and the VRS height follow
  // (they stayed the config's robot's).
  const PolylocConfig lab = loadConfig(kSource + "/maps/config/lab.yaml");
  const std::string sc = dir.write("big.yaml", "config: " + kSource + "/maps/config/lab.yaml\n"
                                               "robot: {radius: 0.45, height: 1.6, kinematics: omni}\n"
                                               "route: {waypoints: [[1, 2], [3, 2]]}\n");
  const Scenario s = loadScenario(sc);
  EXPECT_TRUE(s.config.mcl.motion.omni);
  EXPECT_NEAR(s.config.mcl.clearance, particleClearance(s.config.robot, s.config.mcl), 1e-12);
  EXPECT_GT(s.config.mcl.clearance, lab.mcl.clearance + 0.05);
  EXPECT_DOUBLE_EQ(s.config.vrs.robot_height, 1.6);
  // Without a config: the VRS height is the scenario's robot's too (it was the default 1.2 m).
  const std::string bare = dir.write("bare.yaml", "map: " + map + "\nrig: lisa\nrobot: {radius: 0.3, height: 0.8}\n"
                                                  "route: {waypoints: [[1, 2], [3, 2]]}\n");
  const Scenario b = loadScenario(bare);
  EXPECT_DOUBLE_EQ(b.config.vrs.robot_height, 0.8);
  EXPECT_NEAR(b.config.mcl.clearance, particleClearance(b.config.robot, b.config.mcl), 1e-12);
}

TEST(SimConfig, ScenarioErrorsNameKeyFileAndLine) {
  test::TempDir dir;
  {
    const std::string f = dir.write("unknown.yaml", scenarioText("noise:\n  glas: mirror\n"));
    const std::string e = errorOf([&] { loadScenario(f); });
    EXPECT_NE(e.find(f + ":5:"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown key 'noise.glas'"), std::string::npos) << e;
  }
  {
    const std::string f = dir.write("type.yaml", scenarioText("people:\n  - waypoints: [[1, 1]]\n    speed: fast\n"));
    const std::string e = errorOf([&] { loadScenario(f); });
    EXPECT_NE(e.find(f + ":6:"), std::string::npos) << e;
    EXPECT_NE(e.find("people[0].speed: expected a number, got 'fast'"), std::string::npos) << e;
  }
  {
    const std::string f = dir.write("map.yaml", "seed: 2\nmap: no_such_map.obj\nrig: lisa\nroute: {waypoints: [[0, 0]]}\n");
    const std::string e = errorOf([&] { loadScenario(f); });
    EXPECT_NE(e.find(f + ":2:"), std::string::npos) << e;
    EXPECT_NE(e.find("map: map file"), std::string::npos) << e;
    EXPECT_NE(e.find("no_such_map.obj"), std::string::npos) << e;
  }
  {
    const std::string f = dir.write("sensor.yaml", scenarioText("noise:\n  sensors:\n    s301: {sigma: 0.1}\n"));
    const std::string e = errorOf([&] { loadScenario(f); });
    EXPECT_NE(e.find(f + ":6:"), std::string::npos) << e;
    EXPECT_NE(e.find("noise.sensors.s301"), std::string::npos) << e;
  }
  {
    const std::string f = dir.write("glass.yaml", scenarioText("noise: {glass: frosted}\n"));
    EXPECT_NE(errorOf([&] { loadScenario(f); }).find("unknown glass mode 'frosted'"), std::string::npos);
  }
  {
    const std::string f = dir.write("wp.yaml", "config: " + kSource + "/maps/config/lab.yaml\nroute:\n  waypoints: [[1, 2, 3, 4]]\n");
    const std::string e = errorOf([&] { loadScenario(f); });
    EXPECT_NE(e.find(f + ":3:"), std::string::npos) << e;
    EXPECT_NE(e.find("route.waypoints[0]"), std::string::npos) << e;
  }
}

TEST(SimConfig, ScenarioNoiseOverridesByPresetAndName) {
  test::TempDir dir;
  const std::string f = dir.write(
      "n.yaml", scenarioText("noise:\n  sensors:\n    hokuyo_urg04lx: {sigma: 0.02, dropout: 0.1}\n"
                             "    urg_left: {sigma: 0.05}\n    tof_front: {flying_pixel: 0.25, reflectivity: {wall: 0.3}}\n"
                             "odometry: {alpha3: 0.01, rate_hz: 100}\n"
                             "chairs: {random_shift: 0.2, random_rotation: 10}\n"
                             "start_time: 12.5\n"));
  const Scenario s = loadScenario(f);
  const Rig& rig = s.config.rig;
  EXPECT_EQ(s.noise.sensors[rig.find("urg_front")].sigma, 0.02);
  EXPECT_EQ(s.noise.sensors[rig.find("urg_left")].sigma, 0.05);   // the name wins over the preset
  EXPECT_EQ(s.noise.sensors[rig.find("urg_left")].dropout, 0.1);  // and keeps the preset's other keys
  EXPECT_EQ(s.noise.sensors[rig.find("s300_front_left")].sigma, 0.03);
  EXPECT_EQ(s.noise.sensors[rig.find("tof_front")].flying_pixel, 0.25);
  EXPECT_EQ(s.noise.sensors[rig.find("tof_front")].reflectivity.at("wall"), 0.3);
  EXPECT_EQ(s.odometry.noise.alpha3, 0.01);
  EXPECT_EQ(s.odometry.rate_hz, 100);
  EXPECT_NEAR(s.chairs.random_rotation, deg2rad(10), 1e-15);
  EXPECT_EQ(s.start_time_ns, 12500000000LL);
}

}  // namespace polyloc::t_sim_config
