// Offline as online: `localize` weighs each frame after the odometry that covers its stamp, as
// polylocd does (docs/polylocd.md, "Odometry first"), so a recording whose odometry was written
// late gives the same estimates as one written in stamp order; odometry later than the wait
// (0.25 s of the recording's time) does not hold the frames back for ever.
#include "reloc/recording_job.hpp"
#include "reloc/report.hpp"
#include "sim_fixtures.hpp"

#include <polyloc/io/memory_recording.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/embree.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_recording_job_order {

using namespace polyloc;


// The lab tour's messages, odometry written `late_ns` after its stamp (then in write order).
std::shared_ptr<std::vector<RecordedMessage>> withLateOdometry(const test::CaptureWriter& rec, int64_t late_ns) {
  auto msgs = std::make_shared<std::vector<RecordedMessage>>();
  for (const auto& e : rec.entries) {
    const bool odom = std::holds_alternative<msg::Odometry>(e.message);
    msgs->push_back(RecordedMessage{e.topic, e.stamp + (odom ? late_ns : 0), e.stamp, e.message});
  }
  std::stable_sort(msgs->begin(), msgs->end(), [](const auto& a, const auto& b) { return a.log_time_ns < b.log_time_ns; });
  return msgs;
}

reloc::JobResult run(const PolylocConfig& cfg, const Mesh& mesh, const RayCaster& caster,
                     std::shared_ptr<std::vector<RecordedMessage>> msgs) {
  reloc::JobOptions jo;
  jo.input = "lab tour";
  jo.open = [msgs] { return readMemory(msgs); };
  return reloc::runRecordingJob({cfg, mesh, caster, nullptr}, jo);
}

bool samePoses(const reloc::JobResult& a, const reloc::JobResult& b) {
  if (a.frames.size() != b.frames.size()) return false;
  for (size_t i = 0; i < a.frames.size(); ++i) {
    const auto &x = a.frames[i], &y = b.frames[i];
    if (x.stamp_ns != y.stamp_ns || x.status != y.status || !(x.pose.matrix() == y.pose.matrix()) ||
        !(x.covariance == y.covariance))
      return false;
  }
  return true;
}


TEST(RecordingJobOrder, LateOdometryGivesTheSameEstimates) {
  const test::LabTour tour(6);
  const PolylocConfig cfg = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  const Mesh mesh = loadMesh(cfg.map.file, cfg.map.load);
  EmbreeCaster caster(mesh);
  const reloc::JobResult in_order = run(cfg, mesh, caster, withLateOdometry(tour.rec, 0));
  ASSERT_GT(in_order.frames.size(), 20u);
  // Odometry 40 ms late: after two scans of each scanner and four camera frames it covers.
  const reloc::JobResult late = run(cfg, mesh, caster, withLateOdometry(tour.rec, 40'000'000));
  EXPECT_TRUE(samePoses(in_order, late));
  // Later than the wait: the frames go on extrapolated, still on track, but not the same.
  const reloc::JobResult too_late = run(cfg, mesh, caster, withLateOdometry(tour.rec, 600'000'000));
  EXPECT_FALSE(samePoses(in_order, too_late));
  const auto m = reloc::evaluate(too_late);
  ASSERT_TRUE(m);
  EXPECT_LT(m->all.p95_pos_err_m, 0.05);
  EXPECT_GT(too_late.frames.size(), in_order.frames.size() / 2);
}

}  // namespace polyloc::t_recording_job_order
