// The pipeline with the localiser beside it (PipelineOptions::search_beside, polylocd's
// `global_search: beside`): during a global search the frames go on to the VRS and tracks without
// waiting for its rounds, and the poses are those of the inline pipeline, every one, in order.
#include "pipeline/pipeline.hpp"
#include "reloc/topic_router.hpp"
#include "sim_fixtures.hpp"

#include <polyloc/io/message_pose.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/embree.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_pipeline_search {

using namespace polyloc::pipeline;

struct Recorder : PipelineSink {
  std::vector<std::string> poses;  // every estimate field the pose channel carries, as bytes
  std::vector<MclEstimate> estimates;
  int64_t newest_vrs = 0;
  size_t vrs = 0, late = 0;  // poses published after the VRS of a later frame
  void onPose(const MclEstimate& e, const Pose& map_T_odom) override {
    std::string b;
    auto pod = [&](const auto& v) { b.append(reinterpret_cast<const char*>(&v), sizeof v); };
    pod(e.stamp_ns), pod(e.status), pod(e.global_round), pod(e.particles);
    for (double v : {e.pose.x(), e.pose.y(), e.pose.z(), e.pose.yaw(), map_T_odom.x(), map_T_odom.y(), map_T_odom.yaw()}) pod(v);
    for (int k = 0; k < 36; ++k) pod(e.covariance(k / 6, k % 6));
    poses.push_back(b);
    estimates.push_back(e);
    late += newest_vrs > e.stamp_ns;
  }
  void onVrs(const VirtualScan& v) override { newest_vrs = std::max(newest_vrs, v.stamp_ns), ++vrs; }
};

struct Lab {
  test::LabTour tour{8};
  PolylocConfig cfg = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  Mesh map = loadMesh(cfg.map.file, cfg.map.load);
  EmbreeCaster caster{map};
  Lab() {
    // Fewer global particles than lab.yaml's 100,000: the lab is small, and a round still takes
    // far longer than a frame's VRS.
    cfg.mcl.global_particles = 30000;
  }
};

const Lab& lab() {
  static const Lab l;
  return l;
}

// The tour's odometry and scans in recorded order into a pipeline that starts a global search at
// the first stamp; `at(pipe, i)` before entry i.
Recorder feed(PipelineOptions o, const std::function<void(Pipeline&, size_t, int64_t)>& at = {}) {
  const Lab& l = lab();
  Pipeline p(l.cfg, l.map, l.caster, nullptr, o);
  reloc::TopicRouter router(l.cfg.rig, std::vector<bool>(l.cfg.rig.size(), true));
  Recorder rec;
  std::vector<float> ranges;
  const auto& entries = l.tour.rec.entries;
  p.initGlobal(entries.front().stamp);
  for (size_t i = 0; i < entries.size(); ++i) {
    const auto& e = entries[i];
    if (at) at(p, i, e.stamp);
    if (const auto* odom = std::get_if<msg::Odometry>(&e.message)) {
      if (e.topic == "/odom") p.addOdometry(e.stamp, fromMsgPose(odom->pose.pose));
      continue;
    }
    const auto r = router.route(e.topic, e.stamp, e.message, ranges);
    if (r.kind == reloc::TopicRouter::Kind::Frame && !std::holds_alternative<DepthCameraSpec>(l.cfg.rig.sensors[size_t(r.sensor)].spec))
      p.addRanges(size_t(r.sensor), r.stamp_ns, ranges, rec);
  }
  p.finish(rec);
  return rec;
}

double errorAt(const MclEstimate& e) {
  const auto& l = lab();
  const double t = double(e.stamp_ns - l.tour.rec.entries.front().stamp) * 1e-9;
  return (e.pose.translation() - l.tour.sim->groundTruth(t).translation()).head<2>().norm();
}

TEST(PipelineSearch, BesideGivesTheInlinePoses) {
  const Recorder in = feed({});
  PipelineOptions o;
  o.search_beside = true, o.threads = 2;
  const Recorder beside = feed(o);
  ASSERT_GT(in.poses.size(), 20u);
  EXPECT_EQ(beside.poses.size(), in.poses.size());
  size_t differ = 0;
  for (size_t k = 0; k < std::min(in.poses.size(), beside.poses.size()); ++k) differ += in.poses[k] != beside.poses[k];
  EXPECT_EQ(differ, 0u) << "of " << in.poses.size() << " poses";
  EXPECT_EQ(beside.vrs, in.vrs);
  // Inline, a frame's pose goes out before its VRS; beside, the search's rounds ended while
  // later frames had their VRS (a 30,000-particle round against one frame's VRS).
  EXPECT_EQ(in.late, 0u);
  EXPECT_GE(beside.late, 1u);
  size_t searched = 0;
  for (const auto& e : in.estimates) searched += e.global_round > 0;
  EXPECT_GE(searched, 1u);
  // The search found the lab, and the track after it is on the truth.
  ASSERT_FALSE(in.estimates.empty());
  EXPECT_EQ(in.estimates.back().global_round, 0u);
  EXPECT_LT(errorAt(in.estimates.back()), 0.1);
}

// A pose given during the search (control endpoint's SETPOSE) drops the frames queued behind the
// search and the rounds not yet published: no pose older than it comes out after it.
TEST(PipelineSearch, APoseGivenDuringASearchDropsItsBacklog) {
  PipelineOptions o;
  o.search_beside = true, o.threads = 2;
  const auto& entries = lab().tour.rec.entries;
  const size_t half = entries.size() / 2;
  int64_t init_stamp = 0;
  size_t before = 0;
  Recorder rec = feed(o, [&](Pipeline& p, size_t i, int64_t stamp) {
    if (i != half) return;
    init_stamp = stamp;
    before = p.counters().poses;
    const double t = double(stamp - entries.front().stamp) * 1e-9;
    Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Identity() * 1e-4;
    ASSERT_TRUE(p.initPose(lab().tour.sim->groundTruth(t), cov, stamp));
    EXPECT_FALSE(p.searching());
  });
  ASSERT_GT(rec.estimates.size(), before + 5);
  for (size_t k = before; k < rec.estimates.size(); ++k) {
    EXPECT_GE(rec.estimates[k].stamp_ns, init_stamp) << k;
    EXPECT_EQ(rec.estimates[k].global_round, 0u) << k;
  }
  EXPECT_LT(errorAt(rec.estimates.back()), 0.1);
}

// Frames queued behind the search beyond max_queue_bytes: the oldest are dropped and counted,
// and the poses still come in stamp order.
TEST(PipelineSearch, AFullQueueDropsTheOldestFrames) {
  PipelineOptions o;
  o.search_beside = true, o.threads = 1;
  o.max_queue_bytes = 1;  // the frame just given only
  LocalizerWorker::Counters c;
  Recorder rec = feed(o, [&](Pipeline& p, size_t i, int64_t) {
    if (i + 1 == lab().tour.rec.entries.size()) c = p.workerCounters();
  });
  EXPECT_GT(c.dropped, 0u);
  EXPECT_EQ(c.failed, 0u);
  ASSERT_FALSE(rec.estimates.empty());
  for (size_t k = 1; k < rec.estimates.size(); ++k) EXPECT_GT(rec.estimates[k].stamp_ns, rec.estimates[k - 1].stamp_ns) << k;
}

}  // namespace polyloc::t_pipeline_search
