#include "reloc/carmen_eval.hpp"
#include "reloc/recorded_rig.hpp"
#include "reloc/report.hpp"
#include "reloc/topic_router.hpp"

#include <polyloc/eval/scan_alignment.hpp>
#include <polyloc/eval/stats.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/io/memory_recording.hpp>
#include <polyloc/io/recorded_geometry.hpp>
#include <polyloc/mcl/fit_check.hpp>
#include <polyloc/mcl/refine.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>

#include <fmt/core.h>
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

namespace polyloc::reloc {
namespace {

using Clock = std::chrono::steady_clock;
using Messages = std::shared_ptr<const std::vector<RecordedMessage>>;
constexpr uint64_t kGlobalStartStream = 0x474C53ULL << 40;
constexpr uint64_t kFitStream = 0x464954ULL << 40;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A test run and its messages as the jobs read them (shared by the cases of every map style).
struct PreparedRun {
  TestRun run;
  Messages messages;
  std::vector<size_t> positions;  // indices into the test scans
  size_t decimate = 1;
  std::optional<OdometryDrift> drift;  // none: the log's own odometry
};

PreparedRun prepare(TestRun run, std::vector<size_t> positions, size_t decimate, std::optional<OdometryDrift> drift) {
  PreparedRun p;
  p.drift = std::move(drift);
  p.messages = std::make_shared<const std::vector<RecordedMessage>>(std::move(run.messages));
  run.messages.clear();
  p.run = std::move(run);
  p.positions = std::move(positions);
  p.decimate = decimate;
  return p;
}

// The test scans aligned to the mesh around their known poses.
void measureFloor(const RealLog& log, const std::vector<size_t>& test, const Rig& rig, const RayCaster& caster,
                  const MclConfig& mc, const CarmenEvalOptions& o, CarmenMap& m) {
  const int sensor = TopicRouter(rig, {}).sensorForScan(log.topic);
  if (sensor < 0) throw std::runtime_error(fmt::format("{}: rig '{}' has no sensor for {}", o.log, rig.name, log.topic));
  const CounterRng rng(o.seed);
  auto knownPose = [&](const LoggedScan& s) { return Pose::fromXYZRPY(s.pose.x(), s.pose.y(), 0, 0, 0, s.pose.yaw()); };
  // The map's range bias (walls proud of the surfaces, mcl.range_bias), as the localiser takes
  // it off: the median over the test scans at their known poses, so that the floor is the best
  // this map allows a localiser that knows it.
  std::vector<double> biases;
  if (mc.range_bias)
    for (size_t i = 0; i < test.size(); ++i) {
      const LoggedScan& s = log.scans[test[i]];
      const double b = rangeBiasAt(caster, rig, size_t(sensor), s.scan.ranges, knownPose(s));
      if (std::isfinite(b)) biases.push_back(b);
      if (o.progress && i % 8 == 0) o.progress("floor " + m.map.style, 0.5 * double(i) / double(test.size()));
    }
  m.range_bias = biases.empty() ? 0.0 : std::clamp(percentile(biases, 50), -mc.range_bias_max, mc.range_bias_max);
  const float range_max = rig.sensors[size_t(sensor)].beams().range_max;
  for (size_t i = 0; i < test.size(); ++i) {
    const LoggedScan& s = log.scans[test[i]];
    const Pose known = knownPose(s);
    std::vector<float> ranges;
    subtractRangeBias(s.scan.ranges, m.range_bias, range_max, ranges);
    const ScanAlignment a = alignScan(caster, rig, size_t(sensor), ranges, known);
    m.floor_refined += a.refined;
    m.floor_std_along.push_back(a.refined ? a.std_along : std::numeric_limits<double>::infinity());
    const RefineScan scan{size_t(sensor), ranges, Pose()};
    auto fit = [&](const Pose& p) {
      return checkFit(caster, rig, std::span<const RefineScan>(&scan, 1), p, mc.fit.tolerance, mc.fit.beams_per_scan, mc.fit.past_share);
    };
    auto seen = [&](const Pose& p) { return fit(p).seenThrough(); };
    auto displaced = [&](double d, uint64_t k) {
      const double dir = rng.uniform(-M_PI, M_PI, kFitStream + k, i, 0);
      const double yaw = deg2rad(rng.uniform(-10, 10, kFitStream + k, i, 1));
      return Pose::planar(d * std::cos(dir), d * std::sin(dir), 0) * a.pose * Pose::planar(0, 0, yaw);
    };
    m.seen_through_aligned.push_back(seen(a.pose));
    m.explained_aligned.push_back(fit(a.pose).explainedShare());
    m.seen_through_0_5m.push_back(seen(displaced(0.5, 0)));
    m.seen_through_2m.push_back(seen(displaced(2.0, 1)));
    if (!a.refined) ++m.floor_refused[a.refine_reason];
    m.aligned.push_back(a.pose);
    if (o.progress && i % 8 == 0) o.progress("floor " + m.map.style, 0.5 + 0.5 * double(i) / double(test.size()));
  }
}

// The aligned poses of the run's scans as estimates at its stamps, against its truth.
TrajectoryMetrics floorOn(const CarmenMap& m, const TestRun& run, const std::vector<size_t>& positions) {
  std::vector<EstimatedPose> aligned;
  for (size_t k = 0; k < run.truth.size() && k < positions.size(); ++k)
    aligned.push_back({run.truth[k].stamp_ns, m.aligned[positions[k]], MclStatus::Tracking});
  return evaluateTrajectory(aligned, GroundTruth(run.truth));
}

JobOptions jobOptions(const std::string& what, Messages messages, const CarmenEvalOptions& o) {
  JobOptions jo;
  jo.input = fmt::format("{} ({})", o.log, what);
  jo.open = [messages] { return readMemory(messages, "carmen"); };
  jo.plot = o.plot;
  jo.log = o.log_line;
  return jo;
}

Consistency consistencyOf(const JobResult& job, const TestRun& run) {
  std::vector<PublishedPose> published;
  for (const FrameRecord& f : job.frames)
    published.push_back({f.stamp_ns, f.pose, f.covariance.topLeftCorner<2, 2>(), f.status});
  return evaluateConsistency(published, GroundTruth(run.truth));
}

// A case of the matrix before it is localised: what it runs, its floor and its odometry alone.
CarmenCase runCase(const PreparedRun& p, const CarmenMap& m, size_t map_index) {
  CarmenCase c;
  c.map_style = m.map.style;
  c.map = map_index;
  c.odometry = p.drift ? p.drift->name : "own";
  if (p.drift) c.drift = *p.drift;
  c.decimate = p.decimate;
  c.test_positions = p.positions;
  c.stamps = p.run.stamps;
  c.unusable = p.run.unusable;
  c.odometry_messages = p.run.odometry;
  c.odometry_dropped = p.run.odometry_dropped;
  c.run = p.messages;
  if (m.floor) c.floor = floorOn(m, p.run, p.positions);
  std::vector<EstimatedPose> odo;
  for (const auto& q : p.run.odometry_only) odo.push_back({q.stamp_ns, q.pose, MclStatus::Tracking});
  c.odometry_only = evaluateTrajectory(odo, GroundTruth(p.run.truth));
  return c;
}

void localise(CarmenCase& c, const PreparedRun& p, const JobContext& ctx, const CarmenEvalOptions& o) {
  if (!c.unusable.empty()) return;
  JobOptions jo = jobOptions(c.name() + " run", c.run, o);
  if (o.progress) jo.progress = [&](double f, uint64_t) { o.progress(c.name(), f); };
  c.job = runRecordingJob(ctx, jo);
  c.metrics = evaluate(c.job);
  c.consistency = consistencyOf(c.job, p.run);
}

// Stratified random starts over the test scans that still have `updates` scans after them.
std::vector<CarmenGlobalTrial> runGlobal(const PreparedRun& p, const std::string& style, const JobContext& ctx,
                                         const CarmenEvalOptions& o) {
  std::vector<CarmenGlobalTrial> trials;
  const TestRun& run = p.run;
  const size_t n = run.truth.size(), U = o.global_updates;
  if (n <= U || o.global_trials == 0) return trials;
  const CounterRng rng(o.seed);
  const GroundTruth truth(run.truth);
  const double yaw_tol = deg2rad(o.global_yaw_tol_deg);
  for (size_t i = 0; i < o.global_trials; ++i) {
    const double u = (double(i) + rng.uniform(kGlobalStartStream, i)) / double(o.global_trials);
    CarmenGlobalTrial t;
    t.test_index = std::min(n - U - 1, size_t(u * double(n - U)));
    JobOptions jo = jobOptions("global trial", p.messages, o);
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
      t.tracking_beyond_0_5m += r.frames[k].status == MclStatus::Tracking && t.pos_err > 0.5;
      if (!within) t.first_within = -1;
      else if (t.first_within < 0) t.first_within = int(k + 1);
    }
    t.success = t.updates >= U && t.first_within > 0;
    trials.push_back(t);
    if (o.progress) o.progress("global " + style, double(i + 1) / double(o.global_trials));
  }
  return trials;
}

}  // namespace

std::string CarmenCase::name() const { return fmt::format("{}/{}/x{}", map_style, odometry, decimate); }

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
  if (o.map_styles.empty() || (o.drifts.empty() && !o.own) || o.decimations.empty())
    throw std::invalid_argument("eval carmen: no map style, odometry or decimation to run");
  for (const std::string& s : o.map_styles)
    if (describeLogMapStyle(s).empty())
      throw std::invalid_argument(fmt::format("unknown map style '{}' ({})", s, fmt::join(logMapStyles(), ", ")));
  CarmenEvalResult r;
  r.config = o.config.empty() ? defaultCarmenConfig() : loadConfig(o.config, {.map_optional = true, .recorded_rig = true});
  const RealLog log = readRealLog(o.log, o.topic);
  r.log = o.log;
  r.topic = log.topic;
  r.scans = log.scans.size();
  r.log_odometry = log.odometry.size();
  r.rejected_lines = log.stats.rejected;
  r.geometry = describeGeometry(log.scans.front().scan);
  const RealLogSplit split = splitEvenOdd(log);
  const std::vector<size_t> test = decimateScans(split.test_scans, 1, o.test_scans ? o.test_scans : SIZE_MAX);
  r.map_scans = split.map_scans.size();
  r.test_scans = test.size();
  if (r.test_scans < 2) throw std::runtime_error(fmt::format("{}: {} test scans: too few to evaluate", o.log, r.test_scans));

  // The runs, made once: every drift at every decimation, and the log's own odometry.
  std::vector<PreparedRun> runs;  // drift-major, then decimation
  for (const OdometryDrift& d0 : o.drifts) {
    OdometryDrift d = d0;
    d.seed = o.seed;
    for (size_t dec : o.decimations) {
      std::vector<size_t> positions;
      for (size_t k = 0; k < test.size(); k += std::max<size_t>(dec, 1)) positions.push_back(k);
      runs.push_back(prepare(driftRun(log, decimateScans(test, dec), d, o.restamp_hz), positions, dec, d));
    }
  }
  // The reference run: every test scan with the first odometry; the truth of the floor and the
  // run the global trials start in.
  std::optional<PreparedRun> reference_drift;
  if (!o.drifts.empty()) {
    for (const PreparedRun& p : runs)
      if (p.decimate == 1 && p.drift && p.drift->name == o.drifts.front().name) reference_drift = p;
    if (!reference_drift) {
      OdometryDrift d = o.drifts.front();
      d.seed = o.seed;
      std::vector<size_t> positions(test.size());
      for (size_t k = 0; k < test.size(); ++k) positions[k] = k;
      reference_drift = prepare(driftRun(log, test, d, o.restamp_hz), positions, 1, d);
    }
  }
  std::optional<PreparedRun> own;
  if (o.own) {
    std::vector<size_t> positions(test.size());
    for (size_t k = 0; k < test.size(); ++k) positions[k] = k;
    own = prepare(ownOdometryRun(log, test, o.restamp_hz), positions, 1, std::nullopt);
  }
  const PreparedRun& reference = reference_drift ? *reference_drift : *own;
  r.truth = reference.run.truth;
  // The rig made once from a run, for the floor and every job (all runs have the same scans).
  completeRecordedRig(r.config, *readMemory(reference.messages), o.log, o.log_line);

  LogMapOptions mo = o.map;
  mo.seed = o.seed;
  for (size_t mi = 0; mi < o.map_styles.size(); ++mi) {
    const std::string& style = o.map_styles[mi];
    CarmenMap m;
    auto t0 = Clock::now();
    if (o.progress) mo.progress = [&](double f) { o.progress("map " + style, f); };
    m.map = buildLogMap(log, split.map_scans, style, mo);
    m.map_s = since(t0);
    EmbreeOptions eo;
    eo.threads = r.config.mcl.threads;
    const EmbreeCaster caster(m.map.mesh, eo);
    if (o.floor) {
      t0 = Clock::now();
      measureFloor(log, test, r.config.rig, caster, r.config.mcl, o, m);
      std::vector<EstimatedPose> aligned;
      for (size_t k = 0; k < test.size(); ++k) aligned.push_back({r.truth[k].stamp_ns, m.aligned[k], MclStatus::Tracking});
      m.floor = evaluateTrajectory(aligned, GroundTruth(r.truth));
      m.floor_s = since(t0);
    }
    // mcl.caster weighs the particles (grid2d, gpu, ...); Embree keeps the floor and free space.
    const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(m.map.mesh, r.config.rig, r.config.mcl, r.config.mcl.threads);
    const JobContext ctx{r.config, m.map.mesh, caster, weigh.get()};
    auto run = [&](const PreparedRun& p) {
      CarmenCase c = runCase(p, m, mi);
      localise(c, p, ctx, o);
      r.cases.push_back(std::move(c));
    };
    for (const PreparedRun& p : runs) run(p);
    if (own && mi == 0) run(*own);
    if (reference_drift) m.global = runGlobal(*reference_drift, style, ctx, o);
    r.maps.push_back(std::move(m));
  }
  r.wall_s = since(t_start);
  return r;
}

}  // namespace polyloc::reloc
