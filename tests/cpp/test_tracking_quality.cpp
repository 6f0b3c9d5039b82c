// Tracking quality on simulated people: the bundled lab_tour (three people) and a part of the
// crowd scenario (eight) must meet the figures docs/tracking.md reports: CLEAR-MOT MOTA >= 0.9,
// position RMSE <= 0.10 m, at most one identity switch per 100 track-seconds.
#include <polyloc/eval/tracking_quality.hpp>
#include <polyloc/sim/simulator.hpp>

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_quality {

using namespace polyloc;


TrackingQuality evaluate(const std::string& name, double duration, bool odometry = false) {
  const Scenario s = loadScenario(std::string(POLYLOC_SOURCE_DIR) + "/maps/scenarios/" + name + ".yaml");
  TrackingEvalOptions o;
  o.duration = duration;
  o.odometry = odometry;
  return evaluateTracking(s, loadScenarioMap(s), s.config.tracking, o);
}

void expectBounds(const MotMetrics& m, const std::string& what) {
  EXPECT_GE(m.mota, 0.9) << what;
  EXPECT_LE(m.rmse_m, 0.10) << what;
  EXPECT_LE(m.id_switches_per_100s, 1.0) << what;
  EXPECT_GT(m.track_seconds, 20.0) << what;
}


TEST(TrackingQuality, LabTourMeetsTheBounds) {
  const TrackingQuality q = evaluate("lab_tour", 0);
  expectBounds(q.mot, "lab_tour");
  EXPECT_EQ(q.people, 3u);
  EXPECT_EQ(q.counters.rejected, 0u);
  EXPECT_EQ(q.counters.scans, 2 * q.counters.steps);  // both S300 in every step
}

TEST(TrackingQuality, CrowdMeetsTheBounds) {
  const TrackingQuality q = evaluate("crowd", 25);
  expectBounds(q.mot, "crowd, 25 s");
  EXPECT_EQ(q.people, 8u);
  EXPECT_GT(q.mot.ground_truth, 1500u);  // several people in view at every step
}

TEST(TrackingQuality, FramesForPlotsAreInTheMapFrame) {
  const Scenario s = loadScenario(std::string(POLYLOC_SOURCE_DIR) + "/maps/scenarios/crowd.yaml");
  TrackingEvalOptions o;
  o.duration = 5;
  o.odometry = true;
  o.keep_frames = true;
  const TrackingQuality q = evaluateTracking(s, loadScenarioMap(s), s.config.tracking, o);
  ASSERT_EQ(q.frames.size(), q.mot.frames);
  size_t near = 0, total = 0;
  for (const TrackingEvalFrame& f : q.frames)
    for (const TrackState& t : f.tracks) {
      ++total;
      for (const MotObject& g : f.truth) near += (g.position - t.position).norm() < 0.5;
    }
  EXPECT_GT(total, 50u);
  EXPECT_GE(near, total * 9 / 10);  // odometry tracks mapped back onto the people
}

}  // namespace polyloc::t_tracking_quality
