#include "reloc/carmen_eval.hpp"
#include "reloc/recorded_rig.hpp"
#include "reloc/report.hpp"
#include "reloc/topic_router.hpp"

#include <polyloc/eval/scan_alignment.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/io/memory_recording.hpp>
#include <polyloc/mcl/fit_check.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/io/recorded_geometry.hpp>

#include <fmt/core.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace polyloc::reloc {
namespace {

using Clock = std::chrono::steady_clock;
constexpr uint64_t kGlobalStartStream = 0x474C53ULL << 40;
constexpr uint64_t kFitStream = 0x464954ULL << 40;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The even scans at their known poses into a grid, extruded to a mesh.
void buildMap(const RealLog& log, const RealLogSplit& split, const CarmenEvalOptions& o, CarmenEvalResult& r) {
  ScanMapper mapper(o.mapper);
  for (size_t k = 0; k < split.map_scans.size(); ++k) {
    const LoggedScan& s = log.scans[split.map_scans[k]];
    mapper.add(s.pose.x(), s.pose.y(), s.pose.yaw(), s.scan.ranges.data(), s.scan.ranges.size(), s.scan.angle_min,
               s.scan.angle_increment, s.scan.range_min, s.scan.range_max);
    if (o.progress && k % 16 == 0) o.progress("map", double(k) / double(split.map_scans.size()));
  }
  if (mapper.scans() == 0) throw std::runtime_error(fmt::format("{}: no map scan could be used", o.log));
  r.grid = mapper.grid();
  r.mesh = extrudeGrid(r.grid, o.extrude);
}

// The test scans aligned to the mesh around their known poses, as estimates at the run's stamps.
void measureFloor(const RealLog& log, const RealLogSplit& split, const Rig& rig, const RayCaster& caster,
                  const CarmenEvalOptions& o, CarmenEvalResult& r) {
  const int sensor = TopicRouter(rig, {}).sensorForScan(log.topic);
  if (sensor < 0) throw std::runtime_error(fmt::format("{}: rig '{}' has no sensor for {}", o.log, rig.name, log.topic));
  std::vector<EstimatedPose> aligned;
  const CounterRng rng(o.seed);
  for (size_t i = 0; i < split.test_scans.size(); ++i) {
    const LoggedScan& s = log.scans[split.test_scans[i]];
    const Pose known = Pose::fromXYZRPY(s.pose.x(), s.pose.y(), 0, 0, 0, s.pose.yaw());
    const ScanAlignment a = alignScan(caster, rig, size_t(sensor), s.scan.ranges, known);
    r.floor_refined += a.refined;
    r.floor_std_along.push_back(a.refined ? a.std_along : std::numeric_limits<double>::infinity());
    const RefineScan scan{size_t(sensor), s.scan.ranges, Pose()};
    const MclConfig& mc = r.config.mcl;
    auto fit = [&](const Pose& p) {
      return checkFit(caster, rig, std::span<const RefineScan>(&scan, 1), p, mc.fit.tolerance, mc.fit.beams_per_scan);
    };
    auto seen = [&](const Pose& p) { return fit(p).seenThrough(); };
    auto displaced = [&](double d, uint64_t k) {
      const double dir = rng.uniform(-M_PI, M_PI, kFitStream + k, i, 0);
      const double yaw = deg2rad(rng.uniform(-10, 10, kFitStream + k, i, 1));
      return Pose::planar(d * std::cos(dir), d * std::sin(dir), 0) * a.pose * Pose::planar(0, 0, yaw);
    };
    r.seen_through_aligned.push_back(seen(a.pose));
    r.explained_aligned.push_back(fit(a.pose).explainedShare());
    r.seen_through_0_5m.push_back(seen(displaced(0.5, 0)));
    r.seen_through_2m.push_back(seen(displaced(2.0, 1)));
    if (!a.refined) ++r.floor_refused[a.refine_reason];
    aligned.push_back({r.truth[i].stamp_ns, a.pose, MclStatus::Tracking});
    if (o.progress && i % 8 == 0) o.progress("floor", double(i) / double(split.test_scans.size()));
  }
  r.floor = evaluateTrajectory(aligned, GroundTruth(r.truth));
}

using Messages = std::shared_ptr<const std::vector<RecordedMessage>>;

JobOptions jobOptions(const TestRun& run, Messages messages, const CarmenEvalOptions& o) {
  JobOptions jo;
  jo.input = fmt::format("{} ({} run)", o.log, run.name);
  jo.open = [messages] { return readMemory(messages, "carmen"); };
  jo.plot = o.plot;
  jo.log = o.log_line;
  return jo;
}

CarmenVariant runVariant(const TestRun& run, Messages messages, const JobContext& ctx, const CarmenEvalOptions& o) {
  CarmenVariant v;
  v.name = run.name;
  v.stamps = run.stamps;
  v.odometry = run.odometry;
  v.odometry_dropped = run.odometry_dropped;
  v.unusable = run.unusable;
  v.run = std::move(messages);
  if (!v.unusable.empty()) return v;
  JobOptions jo = jobOptions(run, v.run, o);
  if (o.progress) jo.progress = [&](double f, uint64_t) { o.progress(run.name, f); };
  v.job = runRecordingJob(ctx, jo);
  v.metrics = evaluate(v.job);
  std::vector<EstimatedPose> odo;
  for (const auto& p : run.odometry_only) odo.push_back({p.stamp_ns, p.pose, MclStatus::Tracking});
  v.odometry_only = evaluateTrajectory(odo, GroundTruth(run.truth));
  return v;
}

// Stratified random starts over the test scans that still have `updates` scans after them.
std::vector<CarmenGlobalTrial> runGlobal(const TestRun& run, const Messages& messages, const JobContext& ctx,
                                         const CarmenEvalOptions& o) {
  std::vector<CarmenGlobalTrial> trials;
  const size_t n = run.truth.size(), U = o.global_updates;
  if (n <= U || o.global_trials == 0) return trials;
  const CounterRng rng(o.seed);
  const GroundTruth truth(run.truth);
  const double yaw_tol = deg2rad(o.global_yaw_tol_deg);
  for (size_t i = 0; i < o.global_trials; ++i) {
    const double u = (double(i) + rng.uniform(kGlobalStartStream, i)) / double(o.global_trials);
    CarmenGlobalTrial t;
    t.test_index = std::min(n - U - 1, size_t(u * double(n - U)));
    JobOptions jo = jobOptions(run, messages, o);
    jo.plot = false;
    jo.log = nullptr;
    jo.start = StartMode::Global;
    jo.read_from_ns = run.truth[t.test_index].stamp_ns;
    jo.stop_after_updates = U;
    const JobResult r = runRecordingJob(ctx, jo);
    t.updates = r.frames.size();
    t.filter_s = r.filter_s;
    for (size_t k = 0; k < r.frames.size(); ++k) {
      const auto gt = truth.at(r.frames[k].stamp_ns);
      if (!gt) continue;
      t.truth = *gt, t.estimate = r.frames[k].pose;
      t.pos_err = (t.estimate.translation() - gt->translation()).head<2>().norm();
      const double yaw = std::abs(angleDiff(t.estimate.yaw(), gt->yaw()));
      t.yaw_err_deg = rad2deg(yaw);
      const bool within = t.pos_err <= o.global_pos_tol && yaw <= yaw_tol;
      if (!within) t.first_within = -1;
      else if (t.first_within < 0) t.first_within = int(k + 1);
    }
    t.success = t.updates >= U && t.first_within > 0;
    trials.push_back(t);
    if (o.progress) o.progress("global", double(i + 1) / double(o.global_trials));
  }
  return trials;
}

}  // namespace

PolylocConfig defaultCarmenConfig() {
  PolylocConfig c;
  c.file = "(built-in: robot.radius 0.25, rig recorded)";
  c.robot.radius = 0.25;
  c.rig_from_recording = true;
  c.mcl.clearance = particleClearance(c.robot, c.mcl);
  return c;
}

CarmenEvalResult runCarmenEval(const CarmenEvalOptions& o) {
  const auto t_start = Clock::now();
  CarmenEvalResult r;
  r.config = o.config.empty() ? defaultCarmenConfig() : loadConfig(o.config, {.map_optional = true, .recorded_rig = true});
  const RealLog log = readRealLog(o.log, o.topic);
  r.log = o.log;
  r.topic = log.topic;
  r.scans = log.scans.size();
  r.log_odometry = log.odometry.size();
  r.rejected_lines = log.stats.rejected;
  r.geometry = describeGeometry(log.scans.front().scan);
  const RealLogSplit split = splitEvenOdd(log, o.every);
  r.map_scans = split.map_scans.size();
  r.test_scans = split.test_scans.size();
  if (r.test_scans < 2) throw std::runtime_error(fmt::format("{}: {} test scans: too few to evaluate", o.log, r.test_scans));

  auto t0 = Clock::now();
  buildMap(log, split, o, r);
  r.map_s = since(t0);

  OdometryDrift drift = o.drift;
  drift.seed = o.seed;
  const TestRun drift_run = driftRun(log, split.test_scans, drift, o.restamp_hz);
  r.truth = drift_run.truth;
  const Messages drift_messages = std::make_shared<const std::vector<RecordedMessage>>(drift_run.messages);

  EmbreeOptions eo;
  eo.threads = r.config.mcl.threads;
  const EmbreeCaster caster(r.mesh, eo);
  // The rig made once from the run, for the floor and every job (the own run has the same scans).
  completeRecordedRig(r.config, *readMemory(drift_messages), o.log, o.log_line);
  if (o.floor) {
    t0 = Clock::now();
    measureFloor(log, split, r.config.rig, caster, o, r);
    r.floor_s = since(t0);
  }
  // mcl.caster weighs the particles (grid2d, gpu, ...); Embree keeps the floor and free space.
  const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(r.mesh, r.config.rig, r.config.mcl, r.config.mcl.threads);
  const JobContext ctx{r.config, r.mesh, caster, weigh.get()};
  for (const std::string& name : o.variants) {
    if (name == "drift") {
      r.variants.push_back(runVariant(drift_run, drift_messages, ctx, o));
    } else if (name == "own") {
      TestRun own = ownOdometryRun(log, split.test_scans, o.restamp_hz);
      auto messages = std::make_shared<const std::vector<RecordedMessage>>(std::move(own.messages));
      r.variants.push_back(runVariant(own, std::move(messages), ctx, o));
    } else {
      throw std::runtime_error(fmt::format("unknown variant '{}' (drift, own)", name));
    }
  }
  r.global = runGlobal(drift_run, drift_messages, ctx, o);
  r.wall_s = since(t_start);
  return r;
}

}  // namespace polyloc::reloc
