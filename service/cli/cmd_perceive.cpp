// polyloc perceive: runs perception over a recording (MCAP, ROS 2 bag, CARMEN) on polylocd's
// pipeline without its localiser (pipeline::Pipeline, perception-only): depth frames through the
// ToF filters (kernels/depth) and, as points, into the virtual range scan (kernels/vrs) with every
// other frame, the level scanners into people tracking (kernels/tracking), at the pose of the
// recording's /ground_truth (what localisation gives) or its odometry. Writes DIR/perception.mcap
// (/vrs, /vrs/localization as LaserScan in base_link, /tracks as polyloc_msgs/TrackArray in map),
// PNG snapshots, and with the simulator's ground-truth topics scores VRS and tracking (docs/vrs.md,
// docs/tracking.md).
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "pipeline/pipeline.hpp"
#include "reloc/topic_router.hpp"
#include "viz/topview.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/eval/mot_metrics.hpp>
#include <polyloc/eval/stats.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/sim/noise.hpp>
#include <polyloc/sim/vrs_truth.hpp>
#include <polyloc/tracking/people_tracker.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <cstring>
#include <functional>
#include <map>
#include <optional>

namespace polyloc::cli {
namespace cmd_perceive_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

using Clock = std::chrono::steady_clock;

struct PerceiveArgs {
  std::string input, config, out, pose = "ground_truth";
  size_t snapshots = 4;
  double vrs_reach = 1.2;  // m: segments scored against the true VRS (where lisa's tilted scanners have looked)
  bool json = false;
};

msg::LaserScan toScan(const VirtualScan& v, const std::vector<float>& ranges, int64_t stamp, const std::string& frame) {
  msg::LaserScan s;
  s.header = {msg::fromNs(stamp), frame};
  s.angle_increment = v.angle_increment;
  s.angle_min = v.angle_min + 0.5f * v.angle_increment;  // LaserScan angles are the rays: segment centres
  s.angle_max = s.angle_min + float(ranges.size() - 1) * v.angle_increment;
  s.range_min = v.range_min, s.range_max = v.range_max;
  s.ranges = ranges;
  return s;
}

msg::TrackArray toTracks(const Tracks& t, int64_t stamp, const std::string& frame) {
  msg::TrackArray a;
  a.header = {msg::fromNs(stamp), frame};
  for (const TrackState& s : t.items)
    a.tracks.push_back({s.id, uint8_t(s.status == TrackStatus::Confirmed ? 1 : s.status == TrackStatus::Deleted ? 2 : 0),
                        s.position.x(), s.position.y(), s.velocity.x(), s.velocity.y(),
                        {s.position_cov(0, 0), s.position_cov(0, 1), s.position_cov(1, 0), s.position_cov(1, 1)}});
  return a;
}

void snapshot(const Mesh& map, const VirtualScan& v, const VirtualRangeScanner& vrs, const Tracks& tracks,
              const std::string& path, double t) {
  const Eigen::Vector2f c = v.map_T_base.translation().head<2>().cast<float>();
  viz::TopView view(Eigen::AlignedBox2f(c - Eigen::Vector2f(5, 5), c + Eigen::Vector2f(5, 5)), 60.f);
  view.drawMeshSlice(map, 0.3f);
  const viz::Color light{200, 200, 200};
  view.drawMeshSlice(map, 0.74f, &light, 1);
  for (const auto& p : vrs.memory().points()) view.drawPoint(p, viz::kBlue, 1);
  const float yaw = float(v.map_T_base.yaw());
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v.ranges[i])) continue;
    const float a = yaw + v.angleOf(i);
    const Eigen::Vector2f p = c + v.ranges[i] * Eigen::Vector2f(std::cos(a), std::sin(a));
    const viz::Color col = v.source[i] & kVrsDanger ? viz::kRed : v.source[i] & kVrsMemory ? viz::kOrange : viz::kBlack;
    view.drawPoint(p, col, 2);
  }
  for (const TrackState& s : tracks.items) {
    if (s.status != TrackStatus::Confirmed) continue;
    view.drawPose(Pose::planar(s.position.x(), s.position.y(), std::atan2(s.velocity.y(), s.velocity.x())), viz::kGreen, 0.25f);
    view.drawText(std::to_string(s.id), s.position.cast<float>() + Eigen::Vector2f(0.3f, 0.3f), viz::kGreen);
  }
  view.drawPose(v.map_T_base, viz::kCyan, 0.3f);
  view.drawLegend(fmt::format("t = {:.1f} s   VRS: black direct, orange memory, red danger; blue memory cells; green tracks", t));
  view.drawScaleBar();
  view.save(path);
}

// The true people at a step: every level scanner's latest /ground_truth/people, beams summed.
struct PeopleTruth {
  std::map<int64_t, msg::TrackArray> recent;  // by stamp
  void add(int64_t stamp, const msg::TrackArray& a) {
    recent[stamp] = a;
    while (!recent.empty() && recent.begin()->first < stamp - 200'000'000) recent.erase(recent.begin());
  }
  std::vector<MotObject> at(int64_t stamp, const Eigen::Vector2d& robot) const {
    std::map<uint32_t, std::pair<msg::Track, uint32_t>> sum;
    for (const auto& [t, a] : recent) {
      if (t > stamp || t < stamp - 100'000'000) continue;
      for (const msg::Track& p : a.tracks) {
        auto& e = sum[p.id];
        e.first = p, e.second += p.status;
      }
    }
    std::vector<MotObject> out;
    for (const auto& [id, e] : sum) {
      const Eigen::Vector2d p(e.first.x, e.first.y);
      // As evaluateTracking counts people: 3 beams on them, walking, within 8 m.
      const bool care = e.second >= 3 && std::hypot(e.first.vx, e.first.vy) >= 0.2 && (p - robot).norm() <= 8.0;
      out.push_back({id, p, care});
    }
    return out;
  }
};

// The outputs of a VRS update, with the tracks of its step. Pipeline::perceive calls onTracks,
// then setMovingObjects and the VRS update, then onVrs: the time between the two is exactly those
// two calls (vrs_update_ms).
struct StepSink final : pipeline::PipelineSink {
  std::function<void(int64_t stamp, const Tracks&, const VirtualScan&)> step;
  std::vector<double> update_ms;
  int64_t stamp = 0;
  const Tracks* tracks = nullptr;  // the tracker's, unchanged until onVrs
  Clock::time_point t0;
  void onTracks(int64_t s, const Tracks& t) override { stamp = s, tracks = &t, t0 = Clock::now(); }
  void onVrs(const VirtualScan& v) override {
    update_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    step(stamp, *tracks, v);
  }
};

void runPerceive(const PerceiveArgs& a) {
  const auto t_start = Clock::now();
  if (a.pose != "ground_truth" && a.pose != "odometry") throw std::runtime_error("--pose must be ground_truth or odometry");
  checkOutputs({{"--input", a.input}, {"--config", a.config}}, {}, {{"--out", a.out}});
  auto reader = openRecording(a.input);
  const PolylocConfig cfg = loadConfig(a.config);
  const Mesh map = loadMesh(cfg.map.file, cfg.map.load);
  std::filesystem::create_directories(a.out);
  reloc::TopicRouter router(cfg.rig, std::vector<bool>(cfg.rig.size(), true));
  // Odometry poses are not in the map's frame: no map (danger zones) for the VRS then.
  pipeline::Pipeline pipe(cfg, a.pose == "ground_truth" ? &map : nullptr);
  auto writer = createMcap(a.out + "/perception.mcap");

  const auto [total, first_ns, last_ns] = spanOf(reader->topics());
  const bool tty = isatty(fileno(stderr));
  std::optional<Pose> pose;
  PeopleTruth truth_people;
  std::map<int64_t, VirtualScan> recent_vrs;      // the last updates, until their truth comes
  std::map<int64_t, std::vector<float>> truth_vrs;  // /ground_truth/vrs, until its update comes
  struct Step {
    int64_t stamp;
    Eigen::Vector2d robot;
    std::vector<MotObject> hypotheses;
  };
  std::optional<Step> step;
  MotAccumulator mot(0.5);  // plain CLEAR-MOT: a person back under a new id is a switch
  bool have_truth_people = false;
  double vrs_sum2 = 0;
  size_t vrs_segments = 0, vrs_missed = 0, frames = 0, no_pose = 0, snapshots = 0;
  std::vector<std::string> pngs;
  // Depth cameras: each frame's image until its amplitude arrives (then the pipeline filters
  // it), and the pixels the filter kept until its artefact tags (the simulator's truth) arrive:
  // the pipeline's result may be another camera's by then.
  struct DepthPending {
    int64_t stamp = -1;
    std::vector<float> depth;
    std::vector<uint8_t> kept;
    bool filtered = false;
  };
  std::vector<DepthPending> depth_pending(cfg.rig.size());
  uint64_t depth_outliers = 0, depth_outliers_removed = 0, depth_valid = 0, depth_valid_kept = 0, depth_frames = 0;
  std::vector<float> ranges;
  auto scoreVrs = [&] {
    for (auto it = truth_vrs.begin(); it != truth_vrs.end();) {
      auto v = recent_vrs.find(it->first);
      if (v == recent_vrs.end()) {
        ++it;
        continue;
      }
      if (it->first - first_ns > 1'000'000'000) {  // once every sensor has spoken
        const VrsError e = compareVirtualScan(v->second.ranges, v->second.source, it->second, v->second.range_max, a.vrs_reach);
        vrs_sum2 += e.rmse_m * e.rmse_m * double(e.segments), vrs_segments += e.segments, vrs_missed += e.missed;
      }
      it = truth_vrs.erase(it);
    }
    while (recent_vrs.size() > 4) recent_vrs.erase(recent_vrs.begin());
    while (truth_vrs.size() > 4) truth_vrs.erase(truth_vrs.begin());
  };
  StepSink sink;
  sink.step = [&](int64_t stamp, const Tracks& tracks, const VirtualScan& v) {
    writer->write("/vrs", stamp, toScan(v, v.ranges, stamp, "base_link"));
    writer->write("/vrs/localization", stamp, toScan(v, v.ranges_max, stamp, "base_link"));
    writer->write("/tracks", stamp, toTracks(tracks, stamp, "map"));
    recent_vrs[stamp] = v;
    scoreVrs();
    // The people truth of a step comes after its scans: score the previous step now.
    if (have_truth_people && step) {
      const double dt = double(stamp - step->stamp) * 1e-9;
      mot.addFrame(dt, truth_people.at(step->stamp, step->robot), step->hypotheses);
    }
    step = Step{stamp, pose->translation().head<2>(), {}};
    for (const TrackState& t : tracks.items)
      if (t.status == TrackStatus::Confirmed) step->hypotheses.push_back({t.id, t.position, true});
    // Snapshots spread over the run.
    const double frac = last_ns > first_ns ? double(stamp - first_ns) / double(last_ns - first_ns) : 0.0;
    if (snapshots < a.snapshots && frac >= (double(snapshots) + 0.5) / double(a.snapshots)) {
      const std::string png = fmt::format("{}/vrs_{}.png", a.out, snapshots++);
      snapshot(map, v, pipe.vrs(), tracks, png, double(stamp - first_ns) * 1e-9);
      pngs.push_back(png);
    }
  };
  std::vector<double>& update_ms = sink.update_ms;
  RecordedMessage m;
  uint64_t read = 0;
  while (reader->next(m)) {
    ++read;
    if (tty && read % 2000 == 0) {
      fmt::print(stderr, "\rperceive {:3.0f}% {}/{} messages", 100.0 * double(read) / double(std::max<uint64_t>(total, 1)), read, total);
      std::fflush(stderr);
    }
    if (const auto* p = std::get_if<msg::PoseStamped>(&m.message); p && m.topic == "/ground_truth") {
      if (a.pose == "ground_truth") pose = fromMsgPose(p->pose), pipe.setPose(*pose);
      continue;
    }
    if (const auto* o = std::get_if<msg::Odometry>(&m.message)) {
      if (a.pose == "odometry") pose = fromMsgPose(o->pose.pose), pipe.setPose(*pose);
      continue;
    }
    if (const auto* t = std::get_if<msg::TrackArray>(&m.message); t && m.topic == "/ground_truth/people") {
      truth_people.add(msg::toNs(t->header.stamp), *t), have_truth_people = true;
      continue;
    }
    if (const auto* s = std::get_if<msg::LaserScan>(&m.message); s && m.topic == "/ground_truth/vrs") {
      // The truth and the VRS of its stamp come in either order: score when both are there.
      truth_vrs[msg::toNs(s->header.stamp)] = s->ranges;
      scoreVrs();
      continue;
    }
    // Depth images: /depth/<camera>/image, /amplitude, /artefacts (truth) share a stamp.
    if (const auto* img = std::get_if<msg::Image>(&m.message); img && m.topic.rfind("/depth/", 0) == 0) {
      const size_t slash = m.topic.rfind('/');
      const int cam = cfg.rig.find(m.topic.substr(7, slash - 7));
      if (cam < 0 || !std::holds_alternative<DepthCameraSpec>(cfg.rig.sensors[size_t(cam)].spec)) continue;
      const auto& spec = std::get<DepthCameraSpec>(cfg.rig.sensors[size_t(cam)].spec);
      const std::string kind = m.topic.substr(slash + 1);
      const int64_t stamp = msg::toNs(img->header.stamp);
      DepthPending& dp = depth_pending[size_t(cam)];
      const size_t n = size_t(spec.width) * size_t(spec.height);
      const bool float_image = img->encoding == "32FC1" && img->width == uint32_t(spec.width) && img->height == uint32_t(spec.height) && img->data.size() == 4 * n;
      if (kind == "image" && float_image) {
        dp.stamp = stamp, dp.filtered = false;
        dp.depth.resize(n);
        std::memcpy(dp.depth.data(), img->data.data(), 4 * n);
      } else if (kind == "amplitude" && float_image && dp.stamp == stamp && pose) {
        std::vector<float> amp(n);
        std::memcpy(amp.data(), img->data.data(), 4 * n);
        pipe.addDepth(size_t(cam), stamp, dp.depth.data(), amp.data(), sink);
        dp.kept = pipe.lastDepth().valid;
        dp.filtered = true, ++depth_frames, ++frames;
      } else if (kind == "artefacts" && dp.filtered && dp.stamp == stamp && img->data.size() == n) {
        for (size_t k = 0; k < n; ++k) {
          const uint8_t bits = img->data[k] & (kArtefactFlyingPixel | kArtefactReflection);
          const bool kept = dp.kept[k];
          if (bits) ++depth_outliers, depth_outliers_removed += !kept;
          else if (std::isfinite(dp.depth[k]) && dp.depth[k] > 0) ++depth_valid, depth_valid_kept += kept;
        }
      }
      continue;
    }
    const reloc::TopicRouter::Result r = router.route(m.topic, m.log_time_ns, m.message, ranges);
    if (r.kind != reloc::TopicRouter::Kind::Frame) continue;
    if (!pose) {
      ++no_pose;
      continue;
    }
    ++frames;
    pipe.addRanges(size_t(r.sensor), r.stamp_ns, ranges, sink);  // sink.step at the trigger scanner's frames
  }
  if (tty) fmt::print(stderr, "\rperceive 100% {}/{} messages\n", read, total);
  writer->close();

  nlohmann::json j = {{"input", a.input}, {"config", a.config}, {"pose", a.pose}, {"frames", frames},
                      {"frames_without_pose", no_pose}, {"vrs_updates", update_ms.size()},
                      {"output", a.out + "/perception.mcap"}, {"snapshots", pngs},
                      {"wall_s", std::chrono::duration<double>(Clock::now() - t_start).count()}};
  std::sort(update_ms.begin(), update_ms.end());
  j["vrs_update_ms_p50"] = update_ms.empty() ? nlohmann::json() : nlohmann::json(percentile(update_ms, 50));
  j["vrs_update_ms_p99"] = update_ms.empty() ? nlohmann::json() : nlohmann::json(percentile(update_ms, 99));
  j["vrs_rmse_m"] = vrs_segments ? nlohmann::json(std::sqrt(vrs_sum2 / double(vrs_segments))) : nlohmann::json();
  j["vrs_scored_segments"] = vrs_segments;
  j["vrs_missed_segments"] = vrs_missed;
  j["vrs_reach_m"] = a.vrs_reach;
  if (have_truth_people) {
    const MotMetrics mm = mot.metrics();
    j["mota"] = mm.mota, j["track_rmse_m"] = mm.rmse_m, j["id_switches_per_100s"] = mm.id_switches_per_100s;
    j["track_seconds"] = mm.track_seconds, j["reentries"] = mm.reentries;
  } else {
    j["mota"] = j["track_rmse_m"] = j["id_switches_per_100s"] = nullptr;
  }
  j["depth_frames"] = depth_frames;
  j["depth_outlier_removed"] = depth_outliers ? nlohmann::json(double(depth_outliers_removed) / double(depth_outliers)) : nlohmann::json();
  j["depth_valid_kept"] = depth_valid ? nlohmann::json(double(depth_valid_kept) / double(depth_valid)) : nlohmann::json();
  const VrsCounters& c = pipe.vrs().counters();
  j["counters"] = {{"vrs_frames", c.frames}, {"vrs_frames_rejected", c.frames_rejected},
                   {"memory_inserted", c.memory_inserted}, {"memory_far", c.memory_far},
                   {"memory_behind", c.memory_behind}, {"memory_moving", c.memory_moving},
                   {"tracking_scans", pipe.people().counters().scans}, {"tracking_rejected", pipe.people().counters().rejected},
                   {"records_rejected", reader->stats().rejected}};
  if (a.json) fmt::print("{}\n", j.dump());
  else
    fmt::print("perceive: {} frames, {} VRS updates (p99 {:.3f} ms), VRS RMSE {}, MOTA {}; wrote {}\n", frames, update_ms.size(),
               update_ms.empty() ? 0.0 : percentile(update_ms, 99), j["vrs_rmse_m"].dump(), j["mota"].dump(), a.out);
}

}  // namespace cmd_perceive_impl

void registerPerceive(CLI::App& app) {
  using namespace cmd_perceive_impl;
  auto a = std::make_shared<PerceiveArgs>();
  CLI::App* c = app.add_subcommand("perceive", "Virtual range scans and people tracking over a recording");
  c->add_option("--input", a->input, "Recording: MCAP, ROS 2 bag, CARMEN log, TUM RGB-D or 7-Scenes folder")->required()->check(CLI::ExistingPath);
  c->add_option("--config", a->config, "polyloc config (map, robot, rig, vrs, tracking)")->required()->check(CLI::ExistingFile);
  c->add_option("--out", a->out, "Output directory: perception.mcap and PNG snapshots")->required();
  c->add_option("--pose", a->pose, "Robot pose: ground_truth (the recording's /ground_truth) or odometry")->capture_default_str();
  c->add_option("--snapshots", a->snapshots, "PNG snapshots spread over the run")->capture_default_str()->check(finiteRange(0, 10000));
  c->add_option("--vrs-reach", a->vrs_reach, "m: segments scored against /ground_truth/vrs")->capture_default_str()->check(finiteRange(0.0, 1e4));
  c->add_flag("--json", a->json, "Summary as one JSON object on stdout");
  c->callback([a] { runPerceive(*a); });
}

}  // namespace polyloc::cli
