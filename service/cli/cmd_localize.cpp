// polyloc localize: runs the Monte-Carlo localiser over a recording (MCAP, ROS 2 bag, CARMEN)
// and writes the estimate after every measurement update as TUM; with ground truth (the
// recording's /ground_truth or --ground-truth) it reports the accuracy (kernels/eval).
// Progress on stderr when it is a terminal; a summary (or --json) on stdout.
#include "cli/commands.hpp"
#include "cli/localize_report.hpp"
#include "cli/localize_topics.hpp"
#include "cli/parse_number.hpp"
#include "viz/localize_plot.hpp"

#include <polyloc/config/polyloc_config.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/tum.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/raycast/embree.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

namespace polyloc::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct LocalizeArgs {
  std::string map, input, config, init, ground_truth, out, plot, csv, sensors;
  std::string init_sigma = "0.1,5";
  bool global = false, json = false;
  size_t plot_particles = 500;
};

std::vector<double> numbers(const std::string& s, const char* option) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ',')) v.push_back(parseNumber(tok, option));
  return v;
}

void progressBar(uint64_t done, uint64_t total, uint64_t updates) {
  const double f = total ? std::min(1.0, double(done) / double(total)) : 0.0;
  const int width = 40, bar = static_cast<int>(f * width);
  fmt::print(stderr, "\rlocalize [{}{}] {:3.0f}% {}/{} messages, {} updates", std::string(bar, '='),
             std::string(width - bar, ' '), 100 * f, done, total, updates);
  std::fflush(stderr);
}

// Warnings once per key; every occurrence still counts where the caller counts it.
struct Warner {
  std::set<std::string> seen;
  void operator()(const std::string& key, const std::string& text) {
    if (seen.insert(key).second) fmt::print(stderr, "polyloc localize: warning: {} (warned once)\n", text);
  }
};

// First /ground_truth pose of a recording (a short second pass), for the default start.
std::optional<StampedPose> firstTruth(const std::string& input) {
  auto reader = openRecording(input);
  RecordedMessage m;
  for (int i = 0; i < 100000 && reader->next(m); ++i)
    if (const auto* p = std::get_if<msg::PoseStamped>(&m.message); p && m.topic == "/ground_truth") {
      const auto& o = p->pose.orientation;
      const Pose pose(Eigen::Quaterniond(o.w, o.x, o.y, o.z), {p->pose.position.x, p->pose.position.y, p->pose.position.z});
      if (isFinite(pose)) return StampedPose{msg::toNs(p->header.stamp) ? msg::toNs(p->header.stamp) : m.log_time_ns, pose};
    }
  return std::nullopt;
}

void runLocalize(const LocalizeArgs& a) {
  const auto t_start = Clock::now();
  if (a.global && !a.init.empty()) throw std::runtime_error("--init and --global exclude each other");
  // The recording first: a missing or unreadable input fails before the slow map load.
  auto reader = openRecording(a.input);
  PolylocConfig cfg = loadConfig(a.config);
  const MclConfig& mcl = cfg.mcl;
  const std::string map_file = a.map.empty() ? cfg.map.file : a.map;
  const Mesh mesh = loadMesh(map_file, cfg.map.load);

  std::vector<bool> enabled(cfg.rig.size(), a.sensors.empty());
  if (!a.sensors.empty()) {
    std::stringstream ss(a.sensors);
    for (std::string name; std::getline(ss, name, ',');) {
      const int s = cfg.rig.find(name);
      if (s < 0) throw std::runtime_error(fmt::format("--sensors: rig '{}' has no sensor '{}'", cfg.rig.name, name));
      enabled[s] = true;
    }
  }
  TopicRouter router(cfg.rig, enabled);

  // Ground truth: the file when given, else what the recording carries on /ground_truth.
  std::vector<StampedPose> truth;
  uint64_t truth_file_rejected = 0;
  if (!a.ground_truth.empty()) {
    TumReader tr(a.ground_truth);
    for (StampedPose p; tr.next(p);) truth.push_back(p);
    truth_file_rejected = tr.rejected();
    for (size_t i = 0; i < tr.warnings().size() && i < 5; ++i) fmt::print(stderr, "polyloc localize: warning: {}\n", tr.warnings()[i]);
  }

  // How the filter starts: --init, --global, else the first ground-truth pose, else global.
  std::optional<StampedPose> start_pose;
  std::string init_mode = "global";
  if (!a.init.empty()) {
    const auto v = numbers(a.init, "--init");
    if (v.size() != 3 && v.size() != 4) throw std::runtime_error("--init: expected x,y,z,yaw (or x,y,yaw), yaw in degrees");
    const double z = v.size() == 4 ? v[2] : 0.0;
    start_pose = StampedPose{0, Pose::fromXYZRPY(v[0], v[1], z, 0, 0, deg2rad(v.back()))};
    init_mode = "pose";
  } else if (!a.global) {
    if (!truth.empty()) start_pose = GroundTruth(truth).poses().front();
    else start_pose = firstTruth(a.input);
    if (start_pose) {
      init_mode = "ground_truth";
      fmt::print(stderr, "polyloc localize: starting from the first ground-truth pose ({:.3f}, {:.3f}, yaw {:.1f} deg)\n",
                 start_pose->pose.x(), start_pose->pose.y(), rad2deg(start_pose->pose.yaw()));
    } else {
      fmt::print(stderr, "polyloc localize: no --init and no ground truth: global localisation\n");
    }
  }
  const auto sigma = numbers(a.init_sigma, "--init-sigma");
  if (sigma.size() != 2 || sigma[0] < 0 || sigma[1] < 0) throw std::runtime_error("--init-sigma: expected xy_m,yaw_deg");
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  cov.diagonal() << sigma[0] * sigma[0], sigma[0] * sigma[0], 0.02 * 0.02, deg2rad(1) * deg2rad(1),
      deg2rad(1) * deg2rad(1), deg2rad(sigma[1]) * deg2rad(sigma[1]);

  EmbreeOptions eo;
  eo.threads = mcl.threads;
  EmbreeCaster caster(mesh, eo);
  Localizer loc(caster, mesh, cfg.rig, mcl);

  std::unique_ptr<TumWriter> tum;
  if (!a.out.empty()) {
    if (auto dir = std::filesystem::path(a.out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    tum = std::make_unique<TumWriter>(a.out);
  }
  const auto [total, first_ns, last_ns] = spanOf(reader->topics());
  const bool tty = isatty(fileno(stderr));

  viz::LocalizePlotData plot;
  std::vector<EstimatedPose> estimates;
  std::vector<StampedPose> stream_truth;
  std::vector<float> ranges;
  Warner warn;
  uint64_t read = 0, unknown_sensor = 0, wrong_size = 0, bad_image = 0, disabled = 0;
  double filter_s = 0;
  bool initialised = false;
  int64_t init_ns = 0;
  size_t next_cloud = 0;  // clouds at 0, 1/3, 2/3 of the run, and the last update
  const double span_ns = std::max<double>(1.0, double(last_ns - first_ns));
  auto snapshot = [&](const MclEstimate& e) {
    viz::LocalizePlotData::Cloud c{double(e.stamp_ns - first_ns) * 1e-9, e.updates, e.pose, {}};
    const ParticleSet& ps = loc.particles();
    const size_t step = std::max<size_t>(1, ps.size() / std::max<size_t>(1, a.plot_particles));
    for (size_t i = 0; i < ps.size(); i += step) c.particles.emplace_back(float(ps.x[i]), float(ps.y[i]));
    return c;
  };
  auto initialise = [&](int64_t stamp) {
    initialised = true;
    init_ns = start_pose && start_pose->stamp_ns ? start_pose->stamp_ns : stamp;
    if (start_pose) loc.initPose(start_pose->pose, cov, init_ns);
    else loc.initGlobal(init_ns);
  };
  auto timed = [&](auto&& f) {
    const auto t0 = Clock::now();
    f();
    filter_s += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  auto t_progress = Clock::now();

  RecordedMessage m;
  while (reader->next(m)) {
    ++read;
    if (tty && (read % 64 == 0) && Clock::now() - t_progress > std::chrono::milliseconds(100)) {
      t_progress = Clock::now();
      progressBar(read, total, loc.counters().updates);
    }
    if (const auto* p = std::get_if<msg::PoseStamped>(&m.message)) {
      if (m.topic != "/ground_truth" || !a.ground_truth.empty()) continue;
      const auto& o = p->pose.orientation;
      const int64_t t = msg::toNs(p->header.stamp) ? msg::toNs(p->header.stamp) : m.log_time_ns;
      stream_truth.push_back({t, Pose(Eigen::Quaterniond(o.w, o.x, o.y, o.z),
                                      {p->pose.position.x, p->pose.position.y, p->pose.position.z})});
      if (a.plot.size() && isFinite(stream_truth.back().pose))
        plot.truth_path.emplace_back(float(p->pose.position.x), float(p->pose.position.y));
      continue;
    }
    if (const auto* o = std::get_if<msg::Odometry>(&m.message)) {
      const auto& q = o->pose.pose.orientation;
      const Pose odom_T_base(Eigen::Quaterniond(q.w, q.x, q.y, q.z),
                             {o->pose.pose.position.x, o->pose.pose.position.y, o->pose.pose.position.z});
      const int64_t t = msg::toNs(o->header.stamp) ? msg::toNs(o->header.stamp) : m.log_time_ns;
      if (!initialised) initialise(t);
      timed([&] { loc.addOdometry(t, odom_T_base); });
      continue;
    }
    const TopicRouter::Result r = router.route(m.topic, m.log_time_ns, m.message, ranges);
    switch (r.kind) {
      case TopicRouter::Kind::Ignored: continue;
      case TopicRouter::Kind::Disabled: ++disabled; continue;
      case TopicRouter::Kind::UnknownSensor: ++unknown_sensor, warn(m.topic, r.why); continue;
      case TopicRouter::Kind::WrongSize: ++wrong_size, warn("size " + m.topic, r.why + ": frame rejected"); continue;
      case TopicRouter::Kind::BadImage: ++bad_image, warn("image " + m.topic, r.why + ": frame rejected"); continue;
      case TopicRouter::Kind::Frame: break;
    }
    if (!initialised) initialise(r.stamp_ns);
    bool updated = false;
    timed([&] { updated = loc.addScan(static_cast<size_t>(r.sensor), r.stamp_ns, ranges); });
    if (!updated) continue;
    const MclEstimate e = loc.estimate();
    estimates.push_back({e.stamp_ns, e.pose, e.status});
    if (tum) tum->write({e.stamp_ns, e.pose});
    if (a.plot.empty()) continue;
    if (isFinite(e.pose)) plot.estimate_path.emplace_back(float(e.pose.x()), float(e.pose.y()));
    if (next_cloud < 3 && double(e.stamp_ns - first_ns) >= next_cloud * span_ns / 3) {
      plot.clouds.push_back(snapshot(e));
      ++next_cloud;
    } else if (next_cloud == 3 || next_cloud == 4) {  // the 4th cloud follows the last update
      if (next_cloud == 4) plot.clouds.pop_back();
      plot.clouds.push_back(snapshot(e));
      next_cloud = 4;
    }
  }
  if (tty) progressBar(read, total, loc.counters().updates), fmt::print(stderr, "\n");
  tum.reset();
  const ReadStats& rs = reader->stats();
  for (size_t i = 0; i < rs.warnings.size() && i < 5; ++i) fmt::print(stderr, "polyloc localize: warning: {}\n", rs.warnings[i]);
  if (!initialised) fmt::print(stderr, "polyloc localize: warning: {}: no odometry and no scans for the rig\n", a.input);

  // Accuracy.
  const bool from_stream = a.ground_truth.empty();
  if (from_stream) truth = std::move(stream_truth);
  else if (a.plot.size())
    for (const auto& p : truth)
      if (isFinite(p.pose)) plot.truth_path.emplace_back(float(p.pose.x()), float(p.pose.y()));
  std::optional<TrajectoryMetrics> metrics;
  if (!truth.empty()) {
    MetricsOptions mo;
    mo.start_ns = init_ns;
    metrics = evaluateTrajectory(estimates, GroundTruth(std::move(truth)), mo);
  }
  if (!a.csv.empty()) writeCsv(a.csv, metrics ? &*metrics : nullptr, estimates);
  const double wall = std::chrono::duration<double>(Clock::now() - t_start).count();
  const MclCounters& c = loc.counters();
  const double ups = filter_s > 0 ? double(c.updates) / filter_s : 0.0;

  if (!a.plot.empty()) {
    plot.title = fmt::format("polyloc localize {} ({}, {} updates, {:.1f} updates/s)",
                             std::filesystem::path(a.input).filename().string(), init_mode, c.updates, ups);
    if (metrics) {
      const auto& s = metrics->all;
      plot.legend = fmt::format("ATE {:.3f} m, p95 {:.3f} m, yaw RMSE {:.2f} deg, p95 {:.2f} deg", s.ate_rmse_m,
                                s.p95_pos_err_m, s.yaw_rmse_deg, s.p95_yaw_err_deg);
      if (metrics->converged_after_s)
        plot.legend += fmt::format("\nconverged after {:.1f} s; then p95 {:.3f} m, {:.2f} deg", *metrics->converged_after_s,
                                   metrics->after_convergence.p95_pos_err_m, metrics->after_convergence.p95_yaw_err_deg);
      else plot.legend += "\nnot converged (0.2 m, 5 deg for 1 s)";
    }
    if (auto dir = std::filesystem::path(a.plot).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    viz::drawLocalization(mesh, plot, a.plot);
  }

  const MclEstimate last = loc.estimate();
  nlohmann::json counters = {{"messages", read},
                             {"records_rejected", rs.rejected},
                             {"odometry", c.odometry},
                             {"odometry_out_of_order", c.odometry_out_of_order},
                             {"odometry_gaps", c.odometry_gaps},
                             {"scans", c.scans},
                             {"scans_rejected", c.scans_rejected + wrong_size + bad_image},
                             {"scans_wrong_size", wrong_size},
                             {"scans_bad_image", bad_image},
                             {"scans_unknown_sensor", unknown_sensor},
                             {"scans_disabled", disabled},
                             {"resamples", c.resamples},
                             {"injected", c.injected},
                             {"refinements", c.refinements},
                             {"refinements_refused", c.refinements_refused},
                             {"relocalizations", c.relocalizations},
                             {"hypotheses", c.hypotheses},
                             {"particles_blocked", c.particles_blocked},
                             {"blocked_ignored", c.blocked_ignored},
                             {"ground_truth_rejected", truth_file_rejected}};
  if (a.json) {
    nlohmann::json j = {{"input", a.input}, {"format", reader->format()}, {"map", map_file}, {"config", a.config},
                        {"init", init_mode}, {"frames", estimates.size()}, {"updates", c.updates},
                        {"updates_per_s", ups}, {"wall_s", wall}, {"filter_s", filter_s},
                        {"particles", last.particles}, {"status", toString(last.status)}, {"counters", counters}};
    if (!a.out.empty()) j["output"] = a.out;
    if (!a.plot.empty()) j["plot"] = a.plot;
    if (metrics) {
      j["ground_truth"] = from_stream ? std::string("/ground_truth") : a.ground_truth;
      j["evaluated_frames"] = metrics->all.frames;
      j["skipped_frames"] = metrics->skipped;
      const nlohmann::json all = summaryJson(metrics->all);  // a named object: items() refers to it
      for (const auto& [k, v] : all.items())
        if (k != "frames") j[k] = v;
      j["converged_after_s"] = metrics->converged_after_s ? num(*metrics->converged_after_s) : nlohmann::json(nullptr);
      j["after_convergence"] = summaryJson(metrics->after_convergence);
      nlohmann::json by_status = nlohmann::json::object();
      for (size_t s = 0; s < metrics->frames_by_status.size(); ++s)
        by_status[toString(static_cast<MclStatus>(s))] = metrics->frames_by_status[s];
      j["frames_by_status"] = by_status;
    }
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("input      {} ({}), {} messages\n", a.input, reader->format(), read);
  fmt::print("start      {}\n", init_mode);
  fmt::print("updates    {} in {:.2f} s of filter time: {:.1f} updates/s ({:.2f} s wall)\n", c.updates, filter_s, ups, wall);
  fmt::print("final      {} ({:.3f}, {:.3f}, yaw {:.1f} deg), {} particles\n", toString(last.status), last.pose.x(),
             last.pose.y(), rad2deg(last.pose.yaw()), last.particles);
  fmt::print("rejected   {} scans ({} wrong size, {} unknown sensor), {} odometry out of order, {} bad records\n",
             c.scans_rejected + wrong_size + bad_image, wrong_size, unknown_sensor, c.odometry_out_of_order, rs.rejected);
  if (metrics) {
    const auto& s = metrics->all;
    fmt::print("accuracy   {} frames: ATE {:.3f} m, p95 {:.3f} m, yaw RMSE {:.2f} deg, p95 {:.2f} deg, z RMSE {:.3f} m, "
               "roll/pitch RMSE {:.2f} deg\n", s.frames, s.ate_rmse_m, s.p95_pos_err_m, s.yaw_rmse_deg,
               s.p95_yaw_err_deg, s.z_rmse_m, s.roll_pitch_rmse_deg);
    if (metrics->converged_after_s) {
      const auto& ac = metrics->after_convergence;
      fmt::print("converged  after {:.1f} s; then p95 {:.3f} m, p95 yaw {:.2f} deg ({} frames)\n",
                 *metrics->converged_after_s, ac.p95_pos_err_m, ac.p95_yaw_err_deg, ac.frames);
    } else {
      fmt::print("converged  never (0.2 m and 5 deg for 1 s)\n");
    }
  }
  if (!a.out.empty()) fmt::print("trajectory {}\n", a.out);
  if (!a.plot.empty()) fmt::print("plot       {}\n", a.plot);
}

}  // namespace

void registerLocalize(CLI::App& app) {
  auto args = std::make_shared<LocalizeArgs>();
  CLI::App& cmd = *app.add_subcommand("localize", "Localise a recorded run with Monte-Carlo localisation on the polygon map");
  cmd.add_option("--input", args->input, "Recording: MCAP, ROS 2 bag (directory, metadata.yaml or .db3), CARMEN log")->required();
  cmd.add_option("--config", args->config, "polyloc config (maps/config/*.yaml): map, rig, mcl")->required();
  cmd.add_option("--map", args->map, "Polygon map (default: the config's)");
  cmd.add_option("--init", args->init, "Start pose x,y,z,yaw (m, deg; or x,y,yaw)");
  cmd.add_flag("--global", args->global, "Global localisation (default without --init: the first ground-truth pose, if any)");
  cmd.add_option("--init-sigma", args->init_sigma, "Start spread xy_m,yaw_deg for --init and ground-truth starts")->capture_default_str();
  cmd.add_option("--ground-truth", args->ground_truth, "Ground truth as TUM (default: the recording's /ground_truth)");
  cmd.add_option("--sensors", args->sensors, "Rig sensors whose frames are used, comma-separated (default: all)");
  cmd.add_option("--out", args->out, "Write the estimate after each update as TUM");
  cmd.add_option("--plot", args->plot, "Draw map, ground truth, estimate and particle clouds as PNG");
  cmd.add_option("--csv", args->csv, "Per-frame estimate (and errors, with ground truth) as CSV");
  cmd.add_flag("--json", args->json, "Print one JSON object (frames, updates, updates_per_s, wall_s, accuracy, counters)");
  cmd.callback([args] { runLocalize(*args); });
}

}  // namespace polyloc::cli
