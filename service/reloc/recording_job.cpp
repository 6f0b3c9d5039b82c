#include "reloc/recording_job.hpp"

#include "reloc/recorded_rig.hpp"

#include <polyloc/io/message_pose.hpp>
#include <polyloc/geometry/domain.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/restamp.hpp>
#include <polyloc/io/stamp_check.hpp>

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace polyloc::reloc {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

std::unique_ptr<RecordingReader> openJobRecording(const JobOptions& o) {
  auto reader = o.open ? o.open() : openRecording(o.input);
  if (o.restamp_hz > 0) reader = restampByOrder(std::move(reader), o.restamp_hz);
  return reader;
}

std::optional<StampedPose> firstTruth(const JobOptions& o, int64_t from_ns) {
  auto reader = openJobRecording(o);
  RecordedMessage m;
  for (int i = 0; i < 100000 && reader->next(m);) {
    if (m.log_time_ns < from_ns) continue;  // skipped without counting: a late segment's start
    ++i;
    if (const auto* p = std::get_if<msg::PoseStamped>(&m.message); p && m.topic == "/ground_truth") {
      const Pose pose = fromMsgPose(p->pose);
      if (domain::validPose(pose)) return StampedPose{msg::toNs(p->header.stamp) ? msg::toNs(p->header.stamp) : m.log_time_ns, pose};
    }
  }
  return std::nullopt;
}

std::vector<bool> sensorMask(const Rig& rig, const std::string& names) {
  if (names.empty()) return {};
  std::vector<bool> mask(rig.size(), false);
  std::stringstream ss(names);
  for (std::string name; std::getline(ss, name, ',');) {
    const int s = rig.find(name);
    if (s < 0) throw std::runtime_error(fmt::format("--sensors: rig '{}' has no sensor '{}'", rig.name, name));
    mask[s] = true;
  }
  return mask;
}

std::vector<EstimatedPose> estimatesOf(const std::vector<FrameRecord>& frames) {
  std::vector<EstimatedPose> e;
  e.reserve(frames.size());
  for (const auto& f : frames) e.push_back({f.stamp_ns, f.pose, f.status});
  return e;
}

JobResult runRecordingJob(const JobContext& ctx, const JobOptions& o) {
  const auto t_start = Clock::now();
  auto reader = openJobRecording(o);
  JobResult res;
  res.input = o.input;
  res.format = reader->format();
  res.keep_from_ns = o.keep_from_ns;
  res.keep_to_ns = o.keep_to_ns;
  auto log = [&](const std::string& s) { if (o.log) o.log(s); };

  std::set<std::string> warned;
  auto warn = [&](const std::string& key, const std::string& text) {
    if (warned.insert(key).second) log(fmt::format("warning: {} (warned once)", text));
  };
  // The rig: the config's, or made (completed) from the recording's scans.
  std::vector<std::string> rig_notes;
  res.rig = needsRecordedRig(ctx.config) ? recordedRig(ctx.config, *openJobRecording(o), o.input, &rig_notes) : ctx.config.rig;
  const Rig& rig = res.rig;
  for (const auto& n : rig_notes) log(n);
  uint64_t truth_file_rejected = 0;
  if (!o.ground_truth_file.empty()) {
    TumReader tr(o.ground_truth_file);
    for (StampedPose p; tr.next(p);) res.truth.push_back(p);
    truth_file_rejected = tr.rejected();
    for (size_t i = 0; i < tr.warnings().size() && i < 5; ++i) log("warning: " + tr.warnings()[i]);
    res.truth_from_stream = false;
  }

  std::optional<StampedPose> start;
  if (o.start == StartMode::Pose) {
    start = StampedPose{0, o.start_pose};
    res.init_mode = "pose";
  } else if (o.start == StartMode::Auto) {
    if (!res.truth.empty()) {
      // A named GroundTruth: poses() of a temporary would dangle in the loop (a random start).
      const GroundTruth truth(res.truth);
      for (const auto& p : truth.poses())
        if (p.stamp_ns >= o.read_from_ns) { start = p; break; }
    } else {
      start = firstTruth(o, o.read_from_ns);
    }
    if (start) {
      res.init_mode = "ground_truth";
      log(fmt::format("starting from the first ground-truth pose ({:.3f}, {:.3f}, yaw {:.1f} deg)", start->pose.x(),
                      start->pose.y(), rad2deg(start->pose.yaw())));
    } else {
      log("no --init and no ground truth: global localisation");
    }
  }
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  const double sxy = o.init_sigma_xy_m, syaw = deg2rad(o.init_sigma_yaw_deg);
  cov.diagonal() << sxy * sxy, sxy * sxy, 0.02 * 0.02, deg2rad(1) * deg2rad(1), deg2rad(1) * deg2rad(1), syaw * syaw;

  Localizer loc(ctx.caster, ctx.mesh, rig, ctx.config.mcl, ctx.weigh);
  if (start)
    if (auto why = loc.checkPose(start->pose, cov))
      throw std::runtime_error(fmt::format("{}: {} (the map covers {})",
                                           res.init_mode == "pose" ? "--init / --init-sigma" : "the first ground-truth pose",
                                           *why, domain::describeArea(ctx.mesh.bounds())));
  TopicRouter router(rig, o.sensors.empty() ? std::vector<bool>(rig.size(), true) : o.sensors);
  const RecordingSpan span = spanOf(reader->topics());
  const int64_t from_ns = std::max(o.read_from_ns, span.first_ns);
  const int64_t to_ns = std::min(o.keep_to_ns, span.last_ns);
  const double progress_ns = std::max<double>(1.0, double(to_ns - from_ns));

  std::vector<float> ranges;
  uint64_t no_range = 0;
  uint64_t read = 0, unknown_sensor = 0, wrong_size = 0, wrong_geometry = 0, bad_image = 0, disabled = 0;
  StampCheck stamps;
  bool initialised = false;
  size_t next_cloud = 0;  // clouds at 0, 1/3, 2/3 of the kept span, and the last update
  auto snapshot = [&](const MclEstimate& e) {
    viz::LocalizePlotData::Cloud c{double(e.stamp_ns - span.first_ns) * 1e-9, e.updates, e.pose, {}};
    const ParticleSet& ps = loc.particles();
    const size_t step = std::max<size_t>(1, ps.size() / std::max<size_t>(1, o.plot_particles));
    for (size_t i = 0; i < ps.size(); i += step) c.particles.emplace_back(float(ps.x[i]), float(ps.y[i]));
    return c;
  };
  auto initialise = [&](int64_t stamp) {
    initialised = true;
    // The filter starts at the message that starts it: a ground-truth pose's own stamp may lie
    // anywhere (a file on another clock), and times in outputs count from here.
    res.init_ns = stamp;
    if (start) loc.initPose(start->pose, cov, res.init_ns);
    else loc.initGlobal(res.init_ns);
  };
  // A ground-truth start begins at the truth's first stamp: odometry before it is history only.
  const int64_t start_after = start && res.init_mode == "ground_truth" ? start->stamp_ns : std::numeric_limits<int64_t>::min();
  uint64_t before_start = 0;
  auto timed = [&](auto&& f) {
    const auto t0 = Clock::now();
    f();
    res.filter_s += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  const int64_t plot_from = std::max(o.keep_from_ns, from_ns);
  const double plot_span = std::max<double>(1.0, double(to_ns - plot_from));

  std::set<std::string> unknown_topics, ignored_topics;  // a few, for the error when nothing matches the rig
  bool any_frame = false;
  // Each frame is weighed after the odometry that covers its stamp (the first message at or after
  // it), as polylocd does (docs/polylocd.md, "Odometry first"): its motion is interpolated, not
  // extrapolated. A frame waits for that odometry at most kOdomWaitNs of the recording's time
  // (a recording without odometry, or with a gap, goes on extrapolated).
  constexpr int64_t kOdomWaitNs = 250'000'000;
  struct Held {
    size_t sensor;
    int64_t stamp_ns;
    std::vector<float> ranges;
  };
  std::deque<Held> held;
  int64_t odom_ns = std::numeric_limits<int64_t>::min();  // stamp of the newest odometry
  bool stop = false;
  // One frame into the filter; its estimate, when it ended a round, into the results.
  auto weigh = [&](size_t sensor, int64_t stamp_ns, std::span<const float> frame) {
    bool updated = false;
    if (o.on_frame) o.on_frame(sensor, stamp_ns, frame);
    timed([&] { updated = loc.addScan(sensor, stamp_ns, frame); });
    if (!updated) return;
    const MclEstimate e = loc.estimate();
    if (o.on_update) o.on_update(e, loc.particles(), loc.odometryAt(e.stamp_ns));
    if (e.stamp_ns < o.keep_from_ns || e.stamp_ns >= o.keep_to_ns) return;  // warm-up
    res.frames.push_back({e.stamp_ns, e.pose, e.covariance, e.status, e.ess, e.particles, e.seen_through, e.refined,
                          e.map_fit});
    if (o.stop_after_updates > 0 && e.updates >= o.stop_after_updates) stop = true;
    if (!o.plot) return;
    if (domain::validPose(e.pose)) res.plot.estimate_path.emplace_back(float(e.pose.x()), float(e.pose.y()));
    if (next_cloud < 3 && double(e.stamp_ns - plot_from) >= next_cloud * plot_span / 3) {
      res.plot.clouds.push_back(snapshot(e));
      ++next_cloud;
    } else if (next_cloud == 3 || next_cloud == 4) {  // the 4th cloud follows the last update
      if (next_cloud == 4) res.plot.clouds.pop_back();
      res.plot.clouds.push_back(snapshot(e));
      next_cloud = 4;
    }
  };
  // The held frames the odometry now covers, or that waited long enough for it (`now`: the
  // newest stamp read), in the order they came.
  auto release = [&](int64_t now) {
    const int64_t waited = now > std::numeric_limits<int64_t>::min() + kOdomWaitNs ? now - kOdomWaitNs : now;
    while (!held.empty() && !stop && (held.front().stamp_ns <= odom_ns || held.front().stamp_ns < waited)) {
      const Held h = std::move(held.front());
      held.pop_front();
      weigh(h.sensor, h.stamp_ns, h.ranges);
    }
  };
  RecordedMessage m;
  while (!stop && reader->next(m)) {
    if (m.log_time_ns < o.read_from_ns) continue;  // before this segment's warm-up
    if (m.log_time_ns >= o.keep_to_ns) break;      // the next segment's span
    ++read;
    if (o.progress && read % 64 == 0) o.progress(std::clamp(double(m.log_time_ns - from_ns) / progress_ns, 0.0, 1.0), loc.counters().updates);
    if (const auto* p = std::get_if<msg::PoseStamped>(&m.message)) {
      if (m.topic != "/ground_truth" || !res.truth_from_stream) continue;
      stamps.add(m.topic, messageStamp(m), read - 1);
      const int64_t t = msg::toNs(p->header.stamp) ? msg::toNs(p->header.stamp) : m.log_time_ns;
      res.truth.push_back({t, fromMsgPose(p->pose)});
      continue;
    }
    if (const auto* od = std::get_if<msg::Odometry>(&m.message)) {
      stamps.add(m.topic, messageStamp(m), read - 1);
      const int64_t t = msg::toNs(od->header.stamp) ? msg::toNs(od->header.stamp) : m.log_time_ns;
      if (!initialised && t >= start_after) initialise(t);
      const Pose odom_T_base = fromMsgPose(od->pose.pose);
      timed([&] { loc.addOdometry(t, odom_T_base); });
      odom_ns = std::max(odom_ns, t);
      release(t);
      continue;
    }
    const TopicRouter::Result r = router.route(m.topic, m.log_time_ns, m.message, ranges);
    // Only the stamps the filter uses are checked: truth topics for people may share a stamp.
    if (r.kind != TopicRouter::Kind::Ignored) stamps.add(m.topic, messageStamp(m), read - 1);
    switch (r.kind) {
      case TopicRouter::Kind::Ignored:
        if (ignored_topics.size() < 8) ignored_topics.insert(m.topic);
        continue;
      case TopicRouter::Kind::Disabled: ++disabled; continue;
      case TopicRouter::Kind::UnknownSensor:
        ++unknown_sensor, warn(m.topic, r.why);
        if (unknown_topics.size() < 8) unknown_topics.insert(m.topic);
        continue;
      case TopicRouter::Kind::WrongSize: ++wrong_size, warn("size " + m.topic, r.why + ": frame rejected"); continue;
      case TopicRouter::Kind::WrongGeometry:
        ++wrong_geometry, warn("geometry " + m.topic, r.why + ": frame rejected (a rig sensor of preset 'recorded' takes the recorded geometry)");
        continue;
      case TopicRouter::Kind::BadImage: ++bad_image, warn("image " + m.topic, r.why + ": frame rejected"); continue;
      case TopicRouter::Kind::Frame: break;
    }
    any_frame = true;
    // A frame without one range that is a distance (all NaN, inf, negative or beyond 1e4 m) is
    // refused by the filter; say why, once per topic.
    if (std::none_of(ranges.begin(), ranges.end(), [](float v) { return std::isfinite(v) && v > 0 && v <= 1e4f; })) {
      ++no_range, warn("range " + m.topic, m.topic + ": a frame with no valid range (all NaN, inf, 0 or beyond 1e4 m): rejected");
      continue;
    }
    if (!initialised) {
      if (r.stamp_ns < start_after) {  // before the ground truth begins: where the robot was is unknown
        ++before_start;
        continue;
      }
      initialise(r.stamp_ns);
    }
    const size_t sensor = static_cast<size_t>(r.sensor);
    if (held.empty() && r.stamp_ns <= odom_ns) weigh(sensor, r.stamp_ns, ranges);
    else held.push_back({sensor, r.stamp_ns, ranges});
    release(r.stamp_ns);
  }
  release(std::numeric_limits<int64_t>::max());  // the end: no more odometry comes
  if (o.progress) o.progress(1.0, loc.counters().updates);
  const ReadStats& rs = reader->stats();
  for (size_t i = 0; i < rs.warnings.size() && i < 5; ++i) res.warnings.push_back(rs.warnings[i]);
  // A recording none of whose topics is a rig sensor's is a mistake (another robot's recording,
  // the wrong config), not an empty success.
  if (!any_frame && unknown_topics.size() + ignored_topics.size() > 0 && o.read_from_ns <= span.first_ns) {
    std::string topics;
    size_t listed = 0;
    for (const auto* set : {&unknown_topics, &ignored_topics})  // sensor topics first
      for (const auto& t : *set)
        if (listed++ < 8) topics += (topics.empty() ? "" : ", ") + t;
    std::string sensors;
    for (const auto& s : rig.sensors) sensors += (sensors.empty() ? "" : ", ") + s.name;
    throw std::runtime_error(fmt::format("{}: no topic matches a sensor of rig '{}' (the recording has {}{}; the rig's sensors are {})",
                                         o.input, rig.name, topics, listed > 8 ? ", ..." : "", sensors));
  }
  if (!initialised) log(fmt::format("warning: {}: no odometry and no scans for the rig", o.input));
  res.stamp_warnings = stamps.warnings();
  res.stamps_bad = stamps.bad();
  for (const auto& w : res.stamp_warnings)
    log(fmt::format("warning: {}{}", w, o.restamp_hz > 0 ? "" : " (--restamp HZ orders the messages by their place in the log)"));


  const MclCounters& c = loc.counters();
  res.counters = {{"messages", read},
                  {"records_rejected", rs.rejected},
                  {"odometry", c.odometry},
                  {"odometry_out_of_order", c.odometry_out_of_order},
                  {"odometry_invalid", c.odometry_invalid},
                  {"odometry_gaps", c.odometry_gaps},
                  {"scans", c.scans},
                  {"scans_used", c.scans - c.scans_rejected},  // weighed or waiting for motion: not refused
                  {"scans_rejected", c.scans_rejected + wrong_size + wrong_geometry + bad_image + no_range},
                  {"scans_wrong_size", wrong_size},
                  {"scans_wrong_geometry", wrong_geometry},
                  {"stamps_not_increasing", stamps.bad()},
                  {"scans_bad_image", bad_image},
                  {"scans_no_valid_range", no_range},
                  {"scans_unknown_sensor", unknown_sensor},
                  {"scans_disabled", disabled},
                  {"scans_before_start", before_start},
                  {"resamples", c.resamples},
                  {"injected", c.injected},
                  {"refinements", c.refinements},
                  {"refinements_refused", c.refinements_refused},
                  {"relocalizations", c.relocalizations},
                  {"contradicted", c.contradicted},
                  {"unfit", c.unfit},
                  {"hypotheses", c.hypotheses},
                  {"recoveries", c.recoveries},
                  {"jumps", c.jumps},
                  {"inconsistent", c.inconsistent},
                  {"particles_blocked", c.particles_blocked},
                  {"blocked_ignored", c.blocked_ignored},
                  {"ground_truth_rejected", truth_file_rejected}};
  const MclEstimate last = loc.estimate();
  res.updates = c.updates;
  res.final_particles = last.particles;
  res.final_status = last.status;
  res.final_pose = last.pose;
  res.final_range_bias = last.range_bias;
  res.final_odometry_scale_translation = last.odometry_scale_translation;
  res.final_odometry_scale_rotation = last.odometry_scale_rotation;
  res.wall_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  return res;
}

}  // namespace polyloc::reloc
