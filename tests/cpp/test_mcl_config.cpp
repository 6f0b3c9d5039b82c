// The `mcl:` config section: defaults, values, and errors that name the key.
#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/mcl/config_yaml.hpp>

#include <gtest/gtest.h>

using namespace polyloc;

TEST(MclConfigYaml, ReadsValuesAndKeepsDefaults) {
  ConfigMap m = ConfigMap::parse("mcl:\n  dof: 6\n  particles: 3000\n  update_min_angle: 5\n"
                                 "  motion: {alpha1: 0.1, drive: omni}\n  beam: {sigma_hit: 0.03}\n",
                                 "t.yaml");
  const MclConfig c = parseMclConfig(m.map("mcl"));
  EXPECT_EQ(c.dof, 6);
  EXPECT_EQ(c.particles, 3000u);
  EXPECT_NEAR(c.update_min_angle, deg2rad(5), 1e-12);
  EXPECT_DOUBLE_EQ(c.motion.alpha1, 0.1);
  EXPECT_TRUE(c.motion.omni);
  EXPECT_DOUBLE_EQ(c.beam.sigma_hit, 0.03);
  EXPECT_DOUBLE_EQ(c.beam.z_hit, MclConfig{}.beam.z_hit);
  EXPECT_EQ(c.min_particles, MclConfig{}.min_particles);
}

TEST(MclConfigYaml, UnknownKeysAndBadValuesNameTheKey) {
  auto error = [](const std::string& text) {
    try {
      ConfigMap m = ConfigMap::parse(text, "t.yaml");
      parseMclConfig(m.map("mcl"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("mcl:\n  particels: 10\n").find("particels"), std::string::npos);
  EXPECT_NE(error("mcl:\n  beam: {sigma: 1}\n").find("sigma"), std::string::npos);
  EXPECT_NE(error("mcl:\n  dof: 4\n").find("dof"), std::string::npos);
  EXPECT_NE(error("mcl:\n  dof: 4\n").find("t.yaml"), std::string::npos);
  EXPECT_NE(error("mcl:\n  min_particles: 100\n  max_particles: 10\n").find("max_particles"), std::string::npos);
  EXPECT_NE(error("mcl:\n  hypotheses: {count: -1}\n").find("count"), std::string::npos);
  EXPECT_NE(error("mcl:\n  hypotheses: {particles: 0}\n").find("between 1 and"), std::string::npos);
  EXPECT_NE(error("mcl:\n  hypotheses: {seperation: 1}\n").find("seperation"), std::string::npos);
  EXPECT_NE(error("mcl:\n  hypotheses: {screen: {headings: 0}}\n").find("headings"), std::string::npos);
  EXPECT_NE(error("mcl:\n  hypotheses: {screen: {kep: 3}}\n").find("kep"), std::string::npos);
  EXPECT_NE(error("mcl:\n  blocked_max_mass: 2\n").find("blocked_max_mass"), std::string::npos);
}

TEST(MclConfigYaml, HypothesesAndRelocalizationKeys) {
  ConfigMap m = ConfigMap::parse("mcl:\n  relocalize_jump: 2.5\n  blocked_max_mass: 0.8\n"
                                 "  hypotheses: {count: 8, separation_yaw: 30, fresh: 0,\n"
                                 "               screen: {keep: 12, headings: 36, truncate: 0.2}}\n", "t.yaml");
  const MclConfig c = parseMclConfig(m.map("mcl"));
  EXPECT_DOUBLE_EQ(c.relocalize_jump, 2.5);
  EXPECT_DOUBLE_EQ(c.blocked_max_mass, 0.8);
  EXPECT_EQ(c.hypotheses.count, 8u);
  EXPECT_NEAR(c.hypotheses.separation_yaw, deg2rad(30), 1e-12);
  EXPECT_EQ(c.hypotheses.fresh, 0u);
  EXPECT_EQ(c.hypotheses.particles, GlobalHypotheses{}.particles);
  EXPECT_EQ(c.hypotheses.screen.keep, 12u);
  EXPECT_EQ(c.hypotheses.screen.headings, 36u);
  EXPECT_DOUBLE_EQ(c.hypotheses.screen.truncate, 0.2);
  EXPECT_EQ(c.hypotheses.screen.positions, ScanScreenConfig{}.positions);
}

TEST(MclConfigYaml, LabConfigHasAnMclSection) {
  const PolylocConfig c = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  EXPECT_EQ(c.mcl.dof, 3);
  EXPECT_EQ(c.mcl.beams_per_scan, 60u);
}
