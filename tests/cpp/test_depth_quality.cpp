// The depth filter's defaults on a simulated lab tour with the lisa rig's PMD camera: the issue's
// bounds (>= 95% of the flying pixels and reflection outliers removed, >= 95% of the valid
// pixels kept), on the first part of the tour (docs/depth.md has the whole tour's figures).
#include <polyloc/eval/depth_quality.hpp>
#include <polyloc/sim/simulator.hpp>

#include <gtest/gtest.h>

#include <map>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_depth_quality {

using namespace polyloc;

TEST(DepthQuality, DefaultsMeetTheBoundsOnTheLabTour) {
  const Scenario s = loadScenario(std::string(POLYLOC_SOURCE_DIR) + "/maps/scenarios/lab_tour.yaml");
  DepthQualityOptions o;
  o.duration = 40;  // corridor, lab 1 and its door, the workstation
  const DepthQualityResult r = evaluateDepthFilter(s, loadScenarioMap(s), s.config.depth_filter, o);
  EXPECT_EQ(r.sensor, "tof_front");
  EXPECT_EQ(r.frames, 801u);  // 0 .. 40 s at 20 Hz
  EXPECT_GT(r.combined.flying, 10000u);
  EXPECT_GT(r.combined.reflection, 1000u);
  EXPECT_GE(r.combined.outlierRemoved(), 0.95) << "flying " << r.combined.flyingRemoved() << ", reflection "
                                               << r.combined.reflectionRemoved();
  EXPECT_GE(r.combined.validKept(), 0.95);
  ASSERT_EQ(r.per_filter.size(), 3u);
  // Each stage alone does its own part, bounded at 1.5x of what it measured on these 40 s
  // (`polyloc eval depth --scenario maps/scenarios/lab_tour.yaml --duration 40 --json`:
  // jump edges alone remove 17.7% and keep 99.96%, confidence alone 96.0% / 96.7%, validity
  // alone 0% / 99.993%; in the combined run jump edges reject 37,692 pixels first, confidence
  // 234,631). A stage that did nothing fails its row; together they remove more than either.
  std::map<std::string, const DepthFilterQuality*> by;
  for (const DepthFilterQuality& f : r.per_filter) by[f.name] = &f;
  ASSERT_TRUE(by.count("validity") && by.count("jump_edge") && by.count("confidence"));
  const auto& jump = by["jump_edge"]->counts;
  const auto& conf = by["confidence"]->counts;
  EXPECT_GE(jump.outlierRemoved(), 0.177 / 1.5);
  EXPECT_LE(1 - jump.validKept(), 1.5 * 0.00041);
  EXPECT_LE(1 - conf.outlierRemoved(), 1.5 * 0.040);
  EXPECT_LE(1 - conf.validKept(), 1.5 * 0.0334);
  EXPECT_LE(1 - by["validity"]->counts.validKept(), 1.5 * 0.00007);
  EXPECT_GE(by["jump_edge"]->rejected, 37692u * 2 / 3);
  EXPECT_GE(by["confidence"]->rejected, 234631u * 2 / 3);
  EXPECT_GE(r.combined.outlierRemoved() - conf.outlierRemoved(), 0.0085 / 1.5) << "jump edges add nothing to confidence";
}

}  // namespace polyloc::t_depth_quality
