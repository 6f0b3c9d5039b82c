// The `depth_filter:` config section: defaults, values, and errors that name the key.
#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/depth/config_yaml.hpp>
#include <polyloc/geometry/pose.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_depth_config {

using namespace polyloc;

TEST(DepthConfigYaml, EmptySectionGivesTheDefaults) {
  ConfigMap m = ConfigMap::parse("depth_filter: {}\n", "t.yaml");
  const DepthFilterConfig c = parseDepthFilterConfig(m.map("depth_filter"));
  const DepthFilterConfig d;
  EXPECT_FALSE(c.validity.range_min.has_value());
  EXPECT_DOUBLE_EQ(c.jump_edge.min_angle, d.jump_edge.min_angle);
  EXPECT_EQ(c.confidence.iterations, d.confidence.iterations);
  EXPECT_DOUBLE_EQ(c.confidence.threshold, d.confidence.threshold);
  EXPECT_EQ(c.smoothing.method, d.smoothing.method);
}

TEST(DepthConfigYaml, ReadsValuesAndKeepsDefaults) {
  ConfigMap m = ConfigMap::parse("depth_filter:\n"
                                 "  validity: {range_max: 5, amplitude_min: 2}\n"
                                 "  jump_edge: {min_angle: 10, neighbours: 4}\n"
                                 "  confidence: {iterations: 5, colour: none}\n"
                                 "  smoothing: {method: bilateral, size: 7}\n",
                                 "t.yaml");
  const DepthFilterConfig c = parseDepthFilterConfig(m.map("depth_filter"));
  EXPECT_DOUBLE_EQ(*c.validity.range_max, 5.0);
  EXPECT_FALSE(c.validity.range_min.has_value());
  EXPECT_DOUBLE_EQ(c.validity.amplitude_min, 2.0);
  EXPECT_NEAR(c.jump_edge.min_angle, deg2rad(10), 1e-12);
  EXPECT_EQ(c.jump_edge.neighbours, 4);
  EXPECT_TRUE(c.jump_edge.enabled);
  EXPECT_EQ(c.confidence.iterations, 5);
  EXPECT_EQ(c.confidence.colour, "none");
  EXPECT_DOUBLE_EQ(c.confidence.sigma, DepthFilterConfig{}.confidence.sigma);
  EXPECT_EQ(c.smoothing.method, "bilateral");
  EXPECT_EQ(c.smoothing.size, 7);
}

TEST(DepthConfigYaml, UnknownKeysAndBadValuesNameTheKey) {
  auto error = [](const std::string& text) {
    try {
      ConfigMap m = ConfigMap::parse(text, "t.yaml");
      parseDepthFilterConfig(m.map("depth_filter"));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("depth_filter:\n  jump: {}\n").find("jump"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  confidence: {sigma_d: 1}\n").find("sigma_d"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  smoothing: {method: median, size: 4}\n").find("smoothing.size"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  smoothing: {method: gauss}\n").find("smoothing.method"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  jump_edge: {neighbours: 6}\n").find("jump_edge.neighbours"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  confidence: {threshold: 2}\n").find("confidence.threshold"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  validity: {range_min: 3, range_max: 2}\n").find("range_max"), std::string::npos);
  EXPECT_NE(error("depth_filter:\n  validity: {range_min: 3, range_max: 2}\n").find("t.yaml:2"), std::string::npos);
}

TEST(DepthConfigYaml, LabConfigSpellsOutTheDefaults) {
  const PolylocConfig c = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  const DepthFilterConfig d;
  const DepthFilterConfig& l = c.depth_filter;
  EXPECT_EQ(l.jump_edge.enabled, d.jump_edge.enabled);
  EXPECT_NEAR(l.jump_edge.min_angle, d.jump_edge.min_angle, 1e-12);
  EXPECT_EQ(l.jump_edge.mode, d.jump_edge.mode);
  EXPECT_EQ(l.confidence.prediction, d.confidence.prediction);
  EXPECT_EQ(l.confidence.iterations, d.confidence.iterations);
  EXPECT_EQ(l.confidence.reach, d.confidence.reach);
  EXPECT_DOUBLE_EQ(l.confidence.sigma, d.confidence.sigma);
  EXPECT_DOUBLE_EQ(l.confidence.threshold, d.confidence.threshold);
  EXPECT_EQ(l.confidence.colour, d.confidence.colour);
  EXPECT_EQ(l.smoothing.method, d.smoothing.method);
  EXPECT_EQ(l.smoothing.size, d.smoothing.size);
}

}  // namespace polyloc::t_depth_config
