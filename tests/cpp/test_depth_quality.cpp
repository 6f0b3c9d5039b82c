// The depth filter's defaults on a simulated lab tour with the lisa rig's PMD camera: the issue's
// bounds (>= 95% of the flying pixels and reflection outliers removed, >= 95% of the valid
// pixels kept), on the first part of the tour (docs/depth.md has the whole tour's figures).
#include <polyloc/eval/depth_quality.hpp>
#include <polyloc/sim/simulator.hpp>

#include <gtest/gtest.h>

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
  // Each stage alone does part of the work; together they do more than either.
  for (const DepthFilterQuality& f : r.per_filter) EXPECT_LE(f.counts.outlierRemoved(), r.combined.outlierRemoved()) << f.name;
}
