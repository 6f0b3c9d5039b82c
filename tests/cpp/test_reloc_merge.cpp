// polyloc relocalize's pieces without a recording: outcomes survive their byte form (what MPI
// ranks send) exactly, segments merge in time order with the warm-up's ground truth once, and
// the plan splits a recording into the documented spans and deals tasks longest first.
#include "reloc/batch_merge.hpp"
#include "reloc/batch_plan.hpp"
#include "reloc/outcome.hpp"

#include <gtest/gtest.h>

namespace polyloc::reloc::t_reloc_merge {  // the file's own: the suite is compiled in batches (unity build)
namespace {

FrameRecord frame(int64_t t, double x) {
  FrameRecord f;
  f.stamp_ns = t;
  f.pose = Pose::fromXYZRPY(x, 2 * x, 0.1, 0.01, -0.02, 0.3 + x);
  for (int i = 0; i < 36; ++i) f.covariance.data()[i] = 1e-3 * (i + 1) / 7.0;
  f.status = MclStatus::Tracking;
  f.ess = 123.25;
  f.particles = 2000;
  return f;
}

TEST(RelocOutcome, BytesRoundTripExactly) {
  TaskOutcome ok{3, 1, true, "", {"note"}, {}};
  ok.result.input = "a.mcap";
  ok.result.frames = {frame(10, 0.1), frame(20, 1.0 / 3.0)};
  ok.result.truth = {{10, Pose::planar(0.1, 0.2, 0.3)}};
  ok.result.counters = {{"scans", 7}};
  ok.result.plot.estimate_path = {{1.5f, 2.5f}};
  TaskOutcome bad{4, 0, false, "b.mcap: cannot read", {}, {}};
  const auto back = decodeOutcomes(encodeOutcomes({ok, bad}));
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].task, 3u);
  EXPECT_EQ(back[0].rank, 1);
  ASSERT_EQ(back[0].result.frames.size(), 2u);
  const FrameRecord &a = ok.result.frames[1], &b = back[0].result.frames[1];
  EXPECT_EQ(a.stamp_ns, b.stamp_ns);
  EXPECT_NEAR((a.pose.translation() - b.pose.translation()).norm(), 0.0, 1e-15);
  EXPECT_TRUE(a.pose.isApprox(b.pose, 1e-12));
  EXPECT_EQ(a.covariance, b.covariance);
  EXPECT_EQ(back[0].result.counters.at("scans"), 7u);
  EXPECT_FALSE(back[1].ok);
  EXPECT_EQ(back[1].error, "b.mcap: cannot read");
  EXPECT_THROW(decodeOutcomes("not cbor"), std::runtime_error);
}

TEST(RelocMerge, SegmentsInTimeOrderTruthOnce) {
  JobResult s0, s1;
  s0.init_ns = 5;
  s0.frames = {frame(10, 0), frame(20, 0)};
  s1.frames = {frame(30, 0), frame(40, 0)};
  s0.truth = {{10, Pose()}, {20, Pose()}, {25, Pose()}};
  s1.truth = {{20, Pose()}, {25, Pose()}, {30, Pose()}};  // the warm-up overlaps s0
  s0.counters = {{"scans", 2}};
  s1.counters = {{"scans", 3}};
  s0.updates = 2, s1.updates = 4;
  const JobResult m = mergeSegments({s0, s1});
  ASSERT_EQ(m.frames.size(), 4u);
  for (size_t i = 1; i < m.frames.size(); ++i) EXPECT_LT(m.frames[i - 1].stamp_ns, m.frames[i].stamp_ns);
  EXPECT_EQ(m.truth.size(), 4u);
  EXPECT_EQ(m.counters.at("scans"), 5u);
  EXPECT_EQ(m.updates, 6u);
  EXPECT_EQ(m.init_ns, 5);
}

TEST(RelocPlan, WholeRecordingsAndNames) {
  BatchOptions o;
  o.inputs = {"x/a.mcap", "y/a.mcap", "bag/metadata.yaml"};
  const Plan p = planBatch(o);  // no segments: nothing is opened, a bad input fails in its task
  ASSERT_EQ(p.tasks.size(), 3u);
  EXPECT_EQ(p.names, (std::vector<std::string>{"a", "a-2", "bag"}));
  EXPECT_EQ(p.tasks[0].job.start, StartMode::Auto);
  EXPECT_EQ(assignTasks(p, 0, 2).size() + assignTasks(p, 1, 2).size(), 3u);
}

TEST(RelocPlan, UnreadableInputWithSegmentsIsAnInputError) {
  BatchOptions o;
  o.inputs = {"/nonexistent/run.mcap"};
  o.segment_s = 10;
  const Plan p = planBatch(o);
  EXPECT_TRUE(p.tasks.empty());
  EXPECT_NE(p.input_errors[0].find("/nonexistent/run.mcap"), std::string::npos) << p.input_errors[0];
}

}  // namespace
}  // namespace polyloc::reloc
