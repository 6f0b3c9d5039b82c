// The real-log protocol on a log whose truth is known exactly: a CARMEN log written from scans
// ray cast in the asymmetric room along a loop (FLASER with the true laser pose, ODOM lines
// with drift and, as corrected logs have them, a copy of the scan's pose after each scan). The
// protocol must split it, map the even scans, drop the copies, restamp what has no time, align
// the test scans near the truth, and localise them within a few centimetres.
#include "mcl_fixtures.hpp"

#include <polyloc/eval/real_log.hpp>
#include <polyloc/eval/real_log_runs.hpp>
#include <polyloc/eval/stats.hpp>

#include "reloc/carmen_eval.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace polyloc::test {
namespace {

// A FLASER line (180 beams, -90..+89 deg, the CARMEN default) at `p`, and the log's lines for it.
std::string writeLog(const std::vector<Pose>& truth, bool zero_stamps, double odom_drift) {
  const Mesh mesh = asymmetricRoom();
  EmbreeCaster caster(mesh);
  PlanarScannerSpec spec;
  spec.fov_rad = deg2rad(179.0), spec.resolution_rad = deg2rad(1.0), spec.angle_min_rad = deg2rad(-90.0);
  spec.range_max = 50;
  const Sensor laser{"laser", spec, Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)};
  std::string log = "# written by test_real_log_eval\n";
  Pose odom = truth[0];
  CounterRng rng(7);
  char buf[256];
  for (size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {  // odometry drifting 3 cm per step in yaw-dependent direction
      const Pose step = truth[i - 1].inverse() * truth[i];
      odom = odom * Pose::planar(step.x() * (1 + odom_drift), step.y(), step.yaw() + odom_drift * rng.normal(1, i));
    }
    const double t = zero_stamps ? 0.0 : 10.0 + 0.5 * double(i);
    std::snprintf(buf, sizeof buf, "ODOM %.6f %.6f %.6f 0 0 0 %.3f host %.3f\n", odom.x(), odom.y(), odom.yaw(), t, t);
    log += buf;
    const auto ranges = simulateScan(caster, laser, truth[i], 0.005, i);
    log += "FLASER 180";
    for (float r : ranges) {
      std::snprintf(buf, sizeof buf, " %.3f", std::isfinite(r) ? r : 50.0f);
      log += buf;
    }
    const Pose& p = truth[i];
    std::snprintf(buf, sizeof buf, " %.6f %.6f %.6f %.6f %.6f %.6f %.3f host %.3f\n", p.x(), p.y(), p.yaw(), p.x(), p.y(),
                  p.yaw(), t, t);
    log += buf;
    std::snprintf(buf, sizeof buf, "ODOM %.6f %.6f %.6f 0 0 0 0 host 0\n", p.x(), p.y(), p.yaw());  // the corrector's copy
    log += buf;
  }
  return log;
}

std::vector<Pose> loop() {
  std::vector<Pose> out;
  for (const Pose& p : loopTrajectory(120)) out.push_back(p);
  return out;
}

TEST(RealLog, ReadsScansWithPosesAndSplitsThem) {
  TempDir dir;
  const auto truth = loop();
  const RealLog log = readRealLog(dir.write("room.log", writeLog(truth, false, 0.02)));
  EXPECT_EQ(log.topic, "/front_laser");
  ASSERT_EQ(log.scans.size(), truth.size());
  EXPECT_EQ(log.odometry.size(), 2 * truth.size());
  EXPECT_LT(posErr(log.scans[5].pose, truth[5]), 1e-5);
  const RealLogSplit s = splitEvenOdd(log);
  EXPECT_EQ(s.map_scans.size(), 60u);
  EXPECT_EQ(s.test_scans.size(), 60u);
  EXPECT_EQ(s.test_scans[0], 1u);
  EXPECT_EQ(splitEvenOdd(log, 4).test_scans.size(), 30u);  // every other odd scan
  EXPECT_THROW(readRealLog(dir.write("empty.log", "ODOM 0 0 0 0 0 0 1 host 1\n")), std::runtime_error);
}

TEST(RealLog, OwnOdometryDropsTheCopiesAndRestampsWhatHasNoTime) {
  TempDir dir;
  const auto truth = loop();
  const RealLog log = readRealLog(dir.write("room.log", writeLog(truth, true, 0.02)));
  const RealLogSplit s = splitEvenOdd(log);
  const TestRun own = ownOdometryRun(log, s.test_scans, 10.0);
  EXPECT_EQ(own.odometry_dropped, truth.size());
  EXPECT_NE(own.stamps.find("restamped by order at 10 Hz"), std::string::npos) << own.stamps;
  EXPECT_EQ(own.unusable, "");
  ASSERT_EQ(own.truth.size(), s.test_scans.size());
  for (size_t k = 1; k < own.truth.size(); ++k) EXPECT_GT(own.truth[k].stamp_ns, own.truth[k - 1].stamp_ns);
  // The drift run: odometry alone drifts, the stamps increase.
  const TestRun drift = driftRun(log, s.test_scans, OdometryDrift{}, 10.0);
  EXPECT_EQ(drift.odometry, s.test_scans.size());
  const double end_err = posErr(drift.odometry_only.back().pose, drift.truth.back().pose);
  EXPECT_GT(end_err, 0.01);
  EXPECT_EQ(posErr(drift.odometry_only.front().pose, drift.truth.front().pose), 0.0);
}

TEST(RealLog, ALogWhoseOdomLinesAreOnlyCopiesHasNoOdometryOfItsOwn) {
  TempDir dir;
  std::string log;
  for (const std::string& line : [&] {
         std::vector<std::string> v;
         const std::string all = writeLog(loop(), false, 0.02);
         for (size_t i = 0, j; i < all.size(); i = j + 1) v.push_back(all.substr(i, (j = all.find('\n', i)) - i));
         return v;
       }())
    if (!line.starts_with("ODOM") || line.find(" 0 host 0") != std::string::npos) log += line + "\n";
  const RealLog r = readRealLog(dir.write("copies.log", log));
  const TestRun own = ownOdometryRun(r, splitEvenOdd(r).test_scans);
  EXPECT_NE(own.unusable.find("no odometry of its own"), std::string::npos) << own.unusable;
}

TEST(RealLogEval, LocalisesTheOddScansNearTheFloor) {
  TempDir dir;
  reloc::CarmenEvalOptions o;
  o.log = dir.write("room.log", writeLog(loop(), false, 0.02));
  o.global_trials = 3;
  o.global_updates = 8;
  const reloc::CarmenEvalResult r = reloc::runCarmenEval(o);
  EXPECT_EQ(r.test_scans, 60u);
  EXPECT_EQ(r.geometry, "180 beams, -90.00..89.00 deg, step 1.000 deg");
  ASSERT_TRUE(r.floor);
  // The map is the even scans' 5 cm grid, its walls on the cell boundaries: a hit counted in the
  // cell before the wall would put every wall 5 cm into the room (the floor was 6.6 cm before
  // ScanMapperConfig::hit_beyond); half a cell beyond the end point puts it on the surface.
  EXPECT_LT(r.floor->all.ate_rmse_m, 0.01);
  EXPECT_EQ(r.floor_refined, r.test_scans);
  ASSERT_EQ(r.variants.size(), 2u);
  for (const auto& v : r.variants) {
    ASSERT_TRUE(v.metrics) << v.name;
    EXPECT_LT(v.metrics->all.ate_rmse_m, 1.5 * r.floor->all.ate_rmse_m + 0.005) << v.name;
    EXPECT_LT(v.metrics->all.max_pos_err_m, 0.1) << v.name;
    EXPECT_EQ(v.job.counters.at("relocalizations"), 0u) << v.name;
    EXPECT_EQ(v.job.init_mode, "ground_truth") << v.name;
  }
  EXPECT_EQ(r.variants[1].odometry_dropped, 120u);  // the copies
  // The fit check separates the aligned poses from displaced ones.
  EXPECT_LT(percentile(r.seen_through_aligned, 95), 0.1);
  EXPECT_GT(percentile(r.seen_through_2m, 50), 0.25);
  ASSERT_EQ(r.global.size(), 3u);
  for (const auto& t : r.global) EXPECT_TRUE(t.success) << "start " << t.test_index << ": " << t.pos_err << " m";
}

}  // namespace
}  // namespace polyloc::test
