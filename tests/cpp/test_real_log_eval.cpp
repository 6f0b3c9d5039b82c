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

namespace polyloc::test::t_real_log_eval {  // the file's own: the suite is compiled in batches (unity build)
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
  // The drift run: one odometry message per log scan over the test span, odometry alone drifts.
  const TestRun drift = driftRun(log, s.test_scans, parseDrift("mid"), 10.0);
  EXPECT_EQ(drift.odometry, s.test_scans.back() - s.test_scans.front() + 1);
  const double end_err = posErr(drift.odometry_only.back().pose, drift.truth.back().pose);
  EXPECT_GT(end_err, 0.01);
  EXPECT_EQ(posErr(drift.odometry_only.front().pose, drift.truth.front().pose), 0.0);
}

TEST(RealLog, DriftLevelsScaleTheErrorAndDecimationKeepsTheOdometry) {
  TempDir dir;
  const RealLog log = readRealLog(dir.write("room.log", writeLog(loop(), false, 0.02)));
  const RealLogSplit s = splitEvenOdd(log);
  // The same seed: the error of each step scales with the level, so the end error does too.
  auto endErr = [&](const std::string& level) {
    const TestRun run = driftRun(log, s.test_scans, parseDrift(level), 10.0);
    return posErr(run.odometry_only.back().pose, run.truth.back().pose);
  };
  EXPECT_LT(endErr("low"), endErr("mid"));
  EXPECT_LT(endErr("mid"), endErr("high"));
  EXPECT_EQ(endErr("0/0"), endErr("0/0"));
  EXPECT_LT(endErr("0/0"), 1e-6);
  // Every 4th test scan: the odometry at its scans is the full run's (the same noise per log scan).
  const TestRun all = driftRun(log, s.test_scans, parseDrift("high"), 10.0);
  const TestRun quarter = driftRun(log, decimateScans(s.test_scans, 4), parseDrift("high"), 10.0);
  ASSERT_EQ(quarter.truth.size(), 15u);
  for (size_t k = 0; k < quarter.truth.size(); ++k)
    EXPECT_LT(posErr(quarter.odometry_only[k].pose, all.odometry_only[4 * k].pose), 1e-9) << k;
  // Slips: each moves the odometry by 10-30 cm at once (here one every metre on average).
  OdometryDrift slip = parseDrift("0/0+slip");
  EXPECT_EQ(slip.slip_every_m, 10);
  slip.slip_every_m = 1;
  const std::vector<Pose> odo = driftOdometry(log, slip);
  size_t slips = 0;
  for (size_t i = 1; i < odo.size(); ++i) {
    const Pose step = odo[i - 1].inverse() * odo[i];
    const Pose truth = log.scans[i - 1].pose.inverse() * log.scans[i].pose;
    const double off = std::hypot(step.x() - truth.x(), step.y() - truth.y());
    EXPECT_TRUE(off < 1e-6 || (off > 0.099 && off < 0.301)) << i << ": " << off;
    slips += off > 0.099;
  }
  EXPECT_GT(slips, 0u);
  for (const char* bad : {"", "medium", "5", "5/", "-1/1", "5/1+slop", "nan/1"}) EXPECT_THROW(parseDrift(bad), std::invalid_argument) << bad;
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
  ASSERT_EQ(r.maps.size(), 1u);
  const reloc::CarmenMap& m = r.maps[0];
  ASSERT_TRUE(m.floor);
  // The map is the even scans' 5 cm grid, its walls on the cell boundaries: a hit counted in the
  // cell before the wall would put every wall 5 cm into the room (the floor was 6.6 cm before
  // ScanMapperConfig::hit_beyond); half a cell beyond the end point puts it on the surface.
  EXPECT_LT(m.floor->all.ate_rmse_m, 0.01);
  EXPECT_EQ(m.floor_refined, r.test_scans);
  ASSERT_EQ(r.cases.size(), 2u);
  for (const auto& c : r.cases) {
    ASSERT_TRUE(c.metrics) << c.name();
    ASSERT_TRUE(c.floor) << c.name();
    EXPECT_LT(c.metrics->all.ate_rmse_m, 1.5 * c.floor->all.ate_rmse_m + 0.005) << c.name();
    EXPECT_LT(c.metrics->all.max_pos_err_m, 0.1) << c.name();
    EXPECT_EQ(c.job.counters.at("relocalizations"), 0u) << c.name();
    EXPECT_EQ(c.job.init_mode, "ground_truth") << c.name();
    EXPECT_EQ(c.consistency.tracking_beyond, 0u) << c.name();
    EXPECT_EQ(c.consistency.unannounced_jumps, 0u) << c.name();
  }
  EXPECT_EQ(r.cases[0].name(), "polyloc/mid/x1");
  EXPECT_EQ(r.cases[1].name(), "polyloc/own/x1");
  EXPECT_EQ(r.cases[1].odometry_dropped, 120u);  // the copies
  // The fit check separates the aligned poses from displaced ones.
  EXPECT_LT(percentile(m.seen_through_aligned, 95), 0.1);
  EXPECT_GT(percentile(m.seen_through_2m, 50), 0.25);
  ASSERT_EQ(m.global.size(), 3u);
  for (const auto& t : m.global) EXPECT_TRUE(t.success) << "start " << t.test_index << ": " << t.pos_err << " m";
}

TEST(RealLogEval, TheMatrixRunsEveryMapStyleDriftAndDecimation) {
  TempDir dir;
  reloc::CarmenEvalOptions o;
  o.log = dir.write("room.log", writeLog(loop(), false, 0.02));
  o.map_styles = {"endpoint", "noisy"};
  o.drifts = {parseDrift("low"), parseDrift("high+slip")};
  o.decimations = {1, 3};
  o.own = false;
  o.global_trials = 0;
  const reloc::CarmenEvalResult r = reloc::runCarmenEval(o);
  ASSERT_EQ(r.maps.size(), 2u);
  ASSERT_EQ(r.cases.size(), 8u);
  EXPECT_EQ(r.cases[3].name(), "endpoint/high+slip/x3");
  EXPECT_EQ(r.cases[4].name(), "noisy/low/x1");
  for (const auto& c : r.cases) {
    ASSERT_TRUE(c.metrics && c.floor) << c.name();
    EXPECT_EQ(c.metrics->all.frames, c.decimate == 1 ? 60u : 20u) << c.name();
    EXPECT_EQ(c.floor->all.frames, c.metrics->all.frames) << c.name();
    EXPECT_LT(c.metrics->all.max_pos_err_m, 0.5) << c.name();
    EXPECT_EQ(c.consistency.tracking_beyond, 0u) << c.name();
  }
  // The end-point map's walls stand up to a cell (5 cm) in front of the surfaces, more along
  // oblique beams: the range bias found is 5.6 cm here, and with it taken off the floor is near
  // the polyloc map's (< 1 cm above; 6.6 cm without the bias in this small room, where a 180 deg
  // scanner sees the proud walls ahead and to the sides only). The noisy map's walls straddle the
  // surfaces: no bias.
  EXPECT_GT(r.maps[0].range_bias, 0.015);
  EXPECT_LT(r.maps[0].range_bias, 0.08);
  EXPECT_LT(r.maps[0].floor->all.ate_rmse_m, 0.015);
  EXPECT_LT(std::abs(r.maps[1].range_bias), 0.01);
  for (const auto& c : r.cases) EXPECT_NEAR(c.job.final_range_bias, r.maps[c.map].range_bias, 0.01) << c.name();
  o.map_styles = {"square"};
  EXPECT_THROW(reloc::runCarmenEval(o), std::invalid_argument);
}

}  // namespace
}  // namespace polyloc::test
