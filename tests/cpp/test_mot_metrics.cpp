// CLEAR-MOT on sequences made by hand: a perfect tracker, misses, false positives, an identity
// switch, correspondences kept over a closer newcomer, don't-care objects and re-entries.
#include <polyloc/eval/mot_metrics.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_mot_metrics {

using namespace polyloc;


MotObject obj(uint64_t id, double x, double y, bool care = true) { return {id, {x, y}, care}; }


TEST(MotMetrics, PerfectTrackerAndDistances) {
  MotAccumulator acc(0.5);
  for (int k = 0; k < 10; ++k) {
    const std::vector<MotObject> truth = {obj(1, k, 0), obj(2, k, 3)};
    const std::vector<MotObject> hyps = {obj(7, k + 0.1, 0), obj(8, k, 3.2)};
    acc.addFrame(0.1, truth, hyps);
  }
  const MotMetrics m = acc.metrics();
  EXPECT_EQ(m.frames, 10u);
  EXPECT_EQ(m.ground_truth, 20u);
  EXPECT_EQ(m.matches, 20u);
  EXPECT_DOUBLE_EQ(m.mota, 1.0);
  EXPECT_NEAR(m.motp_m, 0.15, 1e-12);
  EXPECT_NEAR(m.rmse_m, std::sqrt((0.01 + 0.04) / 2), 1e-12);
  EXPECT_NEAR(m.track_seconds, 2.0, 1e-12);
  EXPECT_EQ(m.id_switches, 0u);
}

TEST(MotMetrics, MissesFalsePositivesAndTheThreshold) {
  MotAccumulator acc(0.5);
  const std::vector<MotObject> truth = {obj(1, 0, 0), obj(2, 5, 0)};
  acc.addFrame(0.1, truth, std::vector<MotObject>{obj(7, 0.4, 0), obj(8, 5.6, 0), obj(9, 10, 10)});
  const MotMetrics m = acc.metrics();
  EXPECT_EQ(m.matches, 1u);          // 0.4 m: in; 0.6 m: out
  EXPECT_EQ(m.misses, 1u);
  EXPECT_EQ(m.false_positives, 2u);
  EXPECT_DOUBLE_EQ(m.mota, 1.0 - 3.0 / 2.0);
}

TEST(MotMetrics, IdentitySwitchIsCountedOnce) {
  MotAccumulator acc(0.5);
  for (int k = 0; k < 6; ++k) {
    const uint64_t h = k < 3 ? 7 : 9;  // the tracker lost the person and started a new track
    acc.addFrame(0.1, std::vector<MotObject>{obj(1, k * 0.1, 0)}, std::vector<MotObject>{obj(h, k * 0.1, 0)});
  }
  const MotMetrics m = acc.metrics();
  EXPECT_EQ(m.id_switches, 1u);
  EXPECT_NEAR(m.mota, 1.0 - 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(m.id_switches_per_100s, 100.0 / 0.6, 1e-9);
}

TEST(MotMetrics, KeepsTheLastCorrespondenceWhileItHolds) {
  MotAccumulator acc(0.5);
  acc.addFrame(0.1, std::vector<MotObject>{obj(1, 0, 0)}, std::vector<MotObject>{obj(7, 0.3, 0)});
  // A second hypothesis comes closer; the first is still within the threshold: no switch.
  acc.addFrame(0.1, std::vector<MotObject>{obj(1, 0, 0)}, std::vector<MotObject>{obj(7, 0.3, 0), obj(8, 0.05, 0)});
  const MotMetrics m = acc.metrics();
  EXPECT_EQ(m.id_switches, 0u);
  EXPECT_EQ(m.false_positives, 1u);
  EXPECT_NEAR(m.motp_m, 0.3, 1e-12);
}

TEST(MotMetrics, DontCareObjectsAbsorbHypothesesAndAreNoMisses) {
  MotAccumulator acc(0.5);
  // A standing person (don't care) with a track on them, and a hidden one without.
  acc.addFrame(0.1, std::vector<MotObject>{obj(1, 0, 0, false), obj(2, 3, 0, false), obj(3, 6, 0)},
               std::vector<MotObject>{obj(7, 0.1, 0), obj(8, 6, 0)});
  const MotMetrics m = acc.metrics();
  EXPECT_EQ(m.ground_truth, 1u);
  EXPECT_EQ(m.misses, 0u);
  EXPECT_EQ(m.false_positives, 0u);
  EXPECT_EQ(m.matches, 1u);
  EXPECT_DOUBLE_EQ(m.mota, 1.0);
  // A hypothesis between a walking and a standing person goes to the walking one.
  MotAccumulator b(0.5);
  b.addFrame(0.1, std::vector<MotObject>{obj(1, 0, 0, false), obj(2, 0.6, 0)}, std::vector<MotObject>{obj(7, 0.25, 0)});
  EXPECT_EQ(b.metrics().matches, 1u);
  EXPECT_EQ(b.metrics().misses, 0u);
}

TEST(MotMetrics, ComingBackAfterLongOutOfViewIsAReentry) {
  for (double forget : {1.0, std::numeric_limits<double>::infinity()}) {
    MotAccumulator acc(0.5, forget);
    for (int k = 0; k < 40; ++k) {
      const bool away = k >= 10 && k < 30;  // 2 s out of view
      const std::vector<MotObject> truth = {obj(1, 0, 0, !away)};
      const std::vector<MotObject> hyps = away ? std::vector<MotObject>{} : std::vector<MotObject>{obj(k < 10 ? 7 : 8, 0, 0)};
      acc.addFrame(0.1, truth, hyps);
    }
    const MotMetrics m = acc.metrics();
    EXPECT_EQ(m.id_switches + m.reentries, 1u);
    EXPECT_EQ(m.reentries, std::isfinite(forget) ? 1u : 0u);
    EXPECT_EQ(m.misses, 0u);
  }
}

TEST(MotMetrics, NonFiniteObjectsAreSkipped) {
  MotAccumulator acc;
  acc.addFrame(0.1, std::vector<MotObject>{obj(1, std::nan(""), 0)}, std::vector<MotObject>{obj(7, 0, std::nan(""))});
  const MotMetrics m = acc.metrics();
  EXPECT_EQ(m.ground_truth, 0u);
  EXPECT_EQ(m.false_positives, 0u);
  EXPECT_DOUBLE_EQ(m.mota, 0.0);  // no ground truth: 0 by definition
}

}  // namespace polyloc::t_mot_metrics
