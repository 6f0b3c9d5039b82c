// The `mcl:` config section: defaults, values, and errors that name the key.
#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/config_yaml.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mcl_config {

using namespace polyloc;

// The message parseMclConfig throws for a file "t.yaml" holding `text`; empty when it passes.
std::string error(const std::string& text) {
  try {
    ConfigMap m = ConfigMap::parse(text, "t.yaml");
    parseMclConfig(m.map("mcl"));
  } catch (const ConfigError& e) {
    return std::string(e.what());
  }
  return std::string();
}

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
  EXPECT_NE(error("mcl:\n  recovery_min_fit: 1.5\n").find("recovery_min_fit"), std::string::npos);
  EXPECT_NE(error("mcl:\n  innovation_floor_xy: -1\n").find("innovation_floor_xy"), std::string::npos);
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
  const MclConfig g = parseMclConfig(
      ConfigMap::parse("mcl:\n  innovation_floor_xy: 0.05\n  innovation_floor_yaw: 2\n  recovery_min_fit: 0.6\n", "t.yaml")
          .map("mcl"));
  EXPECT_DOUBLE_EQ(g.innovation_floor_xy, 0.05);
  EXPECT_NEAR(g.innovation_floor_yaw, deg2rad(2), 1e-12);
  EXPECT_DOUBLE_EQ(g.recovery_min_fit, 0.6);
  EXPECT_DOUBLE_EQ(g.innovation_gate, MclConfig{}.innovation_gate);
}

TEST(MclConfigYaml, LabConfigHasAnMclSection) {
  const PolylocConfig c = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  EXPECT_EQ(c.mcl.dof, 3);
  EXPECT_EQ(c.mcl.beams_per_scan, 60u);
}

// Issue 31, defect 6: numbers that passed --check and broke the run.
TEST(MclConfigYaml, NumbersAreCheckedBeforeTheyAreNarrowed) {
  // -1 wrapped to 2^64-1 and refused every refinement.
  EXPECT_NE(error("mcl:\n  refine: {min_correspondences: -1}\n").find("refine.min_correspondences"), std::string::npos);
  // 2^32 + 3 became 3 (or 6, or 1): valid-looking values from a wrapped integer.
  EXPECT_NE(error("mcl:\n  dof: 4294967299\n").find("mcl.dof"), std::string::npos);
  EXPECT_NE(error("mcl:\n  threads: 4294967297\n").find("mcl.threads"), std::string::npos);
  EXPECT_NE(error("mcl:\n  refine: {iterations: 4294967306}\n").find("refine.iterations"), std::string::npos);
  EXPECT_NE(error("mcl:\n  refine: {dof: 4294967299}\n").find("refine.dof"), std::string::npos);
  EXPECT_NE(error("mcl:\n  seed: -5\n").find("mcl.seed"), std::string::npos);
  // Each in range, their product 36e9 pairs a round: the memory budget refuses it.
  const std::string screen = error("mcl:\n  hypotheses: {screen: {positions: 1e7, headings: 3600}}\n");
  EXPECT_NE(screen.find("positions x headings"), std::string::npos) << screen;
  EXPECT_NE(screen.find("t.yaml:2:"), std::string::npos) << screen;
  EXPECT_EQ(error("mcl:\n  hypotheses: {screen: {positions: 1e5, headings: 72}}\n"), "");
  // Local recovery's lattice, each number in range: 20,001^2 places x 72 headings.
  const std::string lattice = error("mcl:\n  recovery_max_radius: 100\n  recovery_step: 0.01\n");
  EXPECT_NE(lattice.find("t.yaml:3:"), std::string::npos) << lattice;
  EXPECT_NE(lattice.find("recovery_max_radius / recovery_step gives a lattice of 400040001 places"), std::string::npos) << lattice;
  EXPECT_EQ(error("mcl:\n  recovery_max_radius: 5\n  recovery_step: 0.05\n"), "");
  // A repeated key: the second value was silently dropped.
  const std::string twice = error("mcl:\n  particles: 500\n  particles: 5000\n");
  EXPECT_NE(twice.find("t.yaml:3:3: mcl.particles: repeated key (first at t.yaml:2:3)"), std::string::npos) << twice;
  // In range: still accepted, and 1e3 reads as the integer it is.
  ConfigMap m = ConfigMap::parse("mcl:\n  threads: 2\n  refine: {min_correspondences: 1e3, iterations: 20}\n", "t.yaml");
  const MclConfig c = parseMclConfig(m.map("mcl"));
  EXPECT_EQ(c.threads, 2);
  EXPECT_EQ(c.refine.min_correspondences, 1000u);
  EXPECT_EQ(c.refine.iterations, 20);
}

TEST(MclConfigYaml, BeamsPerScanMeansTheSameInEverySection) {
  // One key, one meaning: 0 takes every valid beam and 100,000 is the most, wherever it is set
  // (mcl's own refused 0, refine's took any size, hypotheses' and the screen's refused 0).
  ConfigMap m = ConfigMap::parse("mcl:\n  beams_per_scan: 0\n  refine: {beams_per_scan: 0}\n  fit: {beams_per_scan: 0}\n"
                                 "  hypotheses: {beams_per_scan: 0, screen: {beams_per_scan: 0}}\n", "t.yaml");
  const MclConfig c = parseMclConfig(m.map("mcl"));
  EXPECT_EQ(c.beams_per_scan, 0u);
  EXPECT_EQ(c.refine.beams_per_scan, 0u);
  EXPECT_EQ(c.fit.beams_per_scan, 0u);
  EXPECT_EQ(c.hypotheses.beams_per_scan, 0u);
  EXPECT_EQ(c.hypotheses.screen.beams_per_scan, 0u);
  for (const char* section : {"", "refine: ", "fit: ", "hypotheses: ", "hypotheses: {screen: "}) {
    const std::string s = section;
    const bool nested = s.find('{') != std::string::npos;
    const std::string text = s.empty() ? "mcl:\n  beams_per_scan: 100001\n"
                                       : "mcl:\n  " + s + "{beams_per_scan: 100001}" + (nested ? "}" : "") + "\n";
    const std::string e = error(text);
    EXPECT_NE(e.find("beams_per_scan: must be between 0 and 100000"), std::string::npos) << text << " -> " << e;
  }
  // 0 = all valid beams: what the samplers do with it.
  BeamSet beams;
  beams.range_min = 0.1f;
  beams.range_max = 10.f;
  for (int b = 0; b < 5; ++b) beams.push(1.f, 0.f, 0.f);
  const std::vector<float> ranges{1.f, 0.f, 2.f, 3.f, 20.f};
  EXPECT_EQ(BeamSensorModel::selectBeams(beams, ranges, 0).size(), 3u);
}

TEST(MclConfigYaml, GpuPlatformsAreCheckedWhenTheFileIs) {
  ConfigMap m = ConfigMap::parse("mcl:\n  gpu_platforms: surfaceless,vulkan\n", "t.yaml");
  try {
    parseMclConfig(m.map("mcl"));
    FAIL() << "an unknown EGL platform passed";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml:2:18: mcl.gpu_platforms: unknown EGL platform 'vulkan'"), std::string::npos) << e.what();
  }
  ConfigMap ok = ConfigMap::parse("mcl:\n  gpu_platforms: device,default\n", "t.yaml");
  EXPECT_EQ(parseMclConfig(ok.map("mcl")).gpu_platforms, "device,default");
}

// docs/localization.md documents `subsample: random`; the config refused it and the code behind
// it was unreachable. It is a choice again: distinct valid beams, in beam order, fixed by seed
// and stream (so any thread count draws the same).
TEST(MclConfigYaml, RandomSubsampleIsReachableAndDeterministic) {
  ConfigMap m = ConfigMap::parse("mcl:\n  subsample: random\n", "t.yaml");
  EXPECT_EQ(parseMclConfig(m.map("mcl")).subsample, "random");
  EXPECT_NE(error("mcl:\n  subsample: every_other\n").find("uniform, random"), std::string::npos);
  BeamSet beams;
  beams.range_min = 0.1f, beams.range_max = 10.f;
  std::vector<float> ranges(200, 2.f);
  for (size_t b = 0; b < ranges.size(); ++b) {
    beams.dx.push_back(1.f), beams.dy.push_back(0.f), beams.dz.push_back(0.f);
    if (b % 10 == 0) ranges[b] = std::nanf("");  // no return: never chosen
  }
  const auto a = BeamSensorModel::selectBeams(beams, ranges, 30, "random", 7, 3);
  ASSERT_EQ(a.size(), 30u);
  EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
  EXPECT_EQ(std::adjacent_find(a.begin(), a.end()), a.end());
  for (size_t b : a) EXPECT_NE(b % 10, 0u);
  EXPECT_EQ(a, BeamSensorModel::selectBeams(beams, ranges, 30, "random", 7, 3));
  EXPECT_NE(a, BeamSensorModel::selectBeams(beams, ranges, 30, "random", 7, 4));
  EXPECT_NE(a, BeamSensorModel::selectBeams(beams, ranges, 30, "uniform", 7, 3));
}

}  // namespace polyloc::t_mcl_config
