// polyloc localize: runs the Monte-Carlo localiser over a recording (MCAP, ROS 2 bag, CARMEN)
// and writes the estimate after every measurement update as TUM; with ground truth (the
// recording's /ground_truth or --ground-truth) it reports the accuracy (kernels/eval).
// Progress on stderr when it is a terminal; a summary (or --json) on stdout.
#include "cli/common_options.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "cli/live_option.hpp"
#include "cli/parse_number.hpp"
#include "reloc/recorded_rig.hpp"
#include "reloc/recording_job.hpp"
#include "reloc/report.hpp"

#include <polyloc/geometry/domain.hpp>
#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

namespace polyloc::cli {
namespace cmd_localize_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

using Clock = std::chrono::steady_clock;

struct LocalizeArgs {
  std::string map, input, config, init, ground_truth, out, plot, csv, sensors;
  std::string init_sigma = "0.1,5";
  double restamp_hz = 0;
  bool global = false, json = false;
  size_t plot_particles = 500;
  LiveArgs live;
};


void progressBar(double f, uint64_t updates) {
  fmt::print(stderr, "\rlocalize {} {:3.0f}%, {} updates", barText(f), 100 * f, updates);
  std::fflush(stderr);
}

void runLocalize(const LocalizeArgs& a) {
  const auto t_start = Clock::now();
  if (a.global && !a.init.empty()) throw std::runtime_error("--init and --global exclude each other");
  checkOutputs({{"--input", a.input}, {"--map", a.map}, {"--config", a.config}, {"--ground-truth", a.ground_truth}},
               {{"--out", a.out}, {"--plot", a.plot}, {"--csv", a.csv}});
  // The recording first: a missing or unreadable input fails before the slow map load.
  openRecording(a.input);
  PolylocConfig cfg = loadConfig(a.config, {.map_optional = !a.map.empty(), .recorded_rig = true});
  const std::string map_file = a.map.empty() ? cfg.map.file : a.map;
  const Mesh mesh = loadMesh(map_file, cfg.map.load);

  reloc::JobOptions jo;
  jo.input = a.input;
  jo.restamp_hz = a.restamp_hz;
  jo.ground_truth_file = a.ground_truth;
  jo.sensors = reloc::sensorMask(cfg.rig, a.sensors);
  // How the filter starts: --init, --global, else the first ground-truth pose, else global.
  if (!a.init.empty()) {
    const Pose p = parseStartPose(a.init, "--init");
    if (auto why = domain::checkPlanar(p.x(), p.y(), p.yaw(), mesh.bounds()))
      throw std::runtime_error(fmt::format("--init: {} (the map covers {})", *why, domain::describeArea(mesh.bounds())));
    jo.start = reloc::StartMode::Pose;
    jo.start_pose = p;
  } else if (a.global) {
    jo.start = reloc::StartMode::Global;
  }
  const auto sigma = parseNumbers(a.init_sigma, "--init-sigma");
  if (sigma.size() != 2 || sigma[0] < 0 || sigma[1] < 0) throw std::runtime_error("--init-sigma: expected xy_m,yaw_deg");
  jo.init_sigma_xy_m = sigma[0];
  jo.init_sigma_yaw_deg = sigma[1];
  jo.plot = !a.plot.empty();
  jo.plot_particles = a.plot_particles;
  jo.log = [](const std::string& s) { fmt::print(stderr, "polyloc localize: {}\n", s); };
  const bool tty = isatty(fileno(stderr));
  if (tty) {
    auto t_progress = std::make_shared<Clock::time_point>(Clock::now());
    jo.progress = [t_progress](double f, uint64_t updates) {
      if (f < 1.0 && Clock::now() - *t_progress < std::chrono::milliseconds(100)) return;
      *t_progress = Clock::now();
      progressBar(f, updates);
    };
  }

  EmbreeOptions eo;
  eo.threads = cfg.mcl.threads;
  EmbreeCaster caster(mesh, eo);
  // The weighing backend's slice height follows the rig (grid2d): complete a recorded one first.
  if (reloc::needsRecordedRig(cfg)) reloc::completeRecordedRig(cfg, *reloc::openJobRecording(jo), a.input, jo.log);
  const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(mesh, cfg.rig, cfg.mcl, cfg.mcl.threads);
  LiveHook live(a.live, mesh, cfg.rig);
  if (live.on()) {
    jo.on_frame = [&live](size_t s, int64_t t, std::span<const float> r) { live.frame(s, t, r); };
    jo.on_update = [&live](const MclEstimate& e, const ParticleSet& p, const Pose& odom) { live.update(e, p, odom); };
  }
  reloc::JobResult r = reloc::runRecordingJob({cfg, mesh, caster, weigh.get()}, jo);
  live.finish();
  if (tty) fmt::print(stderr, "\n");
  for (const auto& w : r.warnings) fmt::print(stderr, "polyloc localize: warning: {}\n", w);
  if (!a.out.empty()) reloc::writeTum(a.out, r.frames);

  const std::optional<TrajectoryMetrics> metrics = reloc::evaluate(r);
  const TrajectoryMetrics* mp = metrics ? &*metrics : nullptr;
  if (!a.csv.empty()) reloc::writeCsv(a.csv, mp, r.frames);
  if (!a.plot.empty()) reloc::drawPlot(mesh, r, mp, a.plot);
  const double wall = std::chrono::duration<double>(Clock::now() - t_start).count();
  const double ups = r.filter_s > 0 ? double(r.updates) / r.filter_s : 0.0;
  // Every scan refused is a failed run, not an empty success: the counts go out, then the error.
  const auto noScanUsed = [&] {
    const auto& c = r.counters;
    if (c.at("scans_used") > 0) return;
    throw std::runtime_error(fmt::format("localize: no scan of {} was used, nothing was localised ({} rejected: {} wrong "
                                         "size, {} wrong geometry, {} without a valid range, {} of no rig sensor)",
                                         a.input, c.at("scans_rejected"), c.at("scans_wrong_size"), c.at("scans_wrong_geometry"),
                                         c.at("scans_no_valid_range"), c.at("scans_unknown_sensor")));
  };

  if (a.json) {
    nlohmann::json j = reloc::resultJson(r, mp);
    j["map"] = map_file;
    j["config"] = a.config;
    j["wall_s"] = wall;
    if (!a.out.empty()) j["output"] = a.out;
    if (!a.plot.empty()) j["plot"] = a.plot;
    if (metrics) j["ground_truth"] = r.truth_from_stream ? std::string("/ground_truth") : a.ground_truth;
    fmt::print("{}\n", j.dump());
    return noScanUsed();
  }
  const auto& c = r.counters;
  fmt::print("input      {} ({}), {} messages\n", a.input, r.format, c.at("messages"));
  fmt::print("start      {}\n", r.init_mode);
  fmt::print("updates    {} in {:.2f} s of filter time: {:.1f} updates/s ({:.2f} s wall)\n", r.updates, r.filter_s, ups, wall);
  fmt::print("final      {} ({:.3f}, {:.3f}, yaw {:.1f} deg), {} particles\n", toString(r.final_status), r.final_pose.x(),
             r.final_pose.y(), rad2deg(r.final_pose.yaw()), r.final_particles);
  fmt::print("rejected   {} scans ({} wrong size, {} unknown sensor), {} odometry out of order, {} bad records\n",
             c.at("scans_rejected"), c.at("scans_wrong_size"), c.at("scans_unknown_sensor"),
             c.at("odometry_out_of_order"), c.at("records_rejected"));
  if (metrics && metrics->all.frames == 0) {
    // No estimate falls within the truth's time span: say so rather than print ATE nan.
    fmt::print("accuracy   none: no estimate lies within the ground truth's time span ({} estimates, {} truth poses; "
               "different clocks? --restamp, or a truth file of this run)\n", r.frames.size(), r.truth.size());
  } else if (metrics) {
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
  noScanUsed();
}

}  // namespace cmd_localize_impl

void registerLocalize(CLI::App& app) {
  using namespace cmd_localize_impl;
  auto args = std::make_shared<LocalizeArgs>();
  CLI::App& cmd = *app.add_subcommand("localize", "Localise a recorded run with Monte-Carlo localisation on the polygon map");
  cmd.add_option("--input", args->input, "Recording: MCAP, ROS 2 bag (directory, metadata.yaml or .db3), CARMEN log, TUM RGB-D or 7-Scenes folder")->required();
  cmd.add_option("--config", args->config, "polyloc config (maps/config/*.yaml): map, rig, mcl")->required();
  addMapOption(cmd, args->map, "Polygon map (default: the config's)");
  cmd.add_option("--init", args->init, "Start pose x,y,yaw or x,y,z,yaw (m, deg)");
  cmd.add_flag("--global", args->global, "Global localisation (default without --init: the first ground-truth pose, if any)");
  cmd.add_option("--init-sigma", args->init_sigma, "Start spread xy_m,yaw_deg for --init and ground-truth starts")->capture_default_str();
  cmd.add_option("--ground-truth", args->ground_truth, "Ground truth as TUM (default: the recording's /ground_truth)");
  cmd.add_option("--restamp", args->restamp_hz, "Restamp every message by its order in the recording at this rate (Hz), for logs whose stamps do not increase")
      ->check(finiteRange(1e-3, 1e9));
  cmd.add_option("--sensors", args->sensors, "Rig sensors whose frames are used, comma-separated (default: all; the filter also weighs only the config's mcl.sensors)");
  cmd.add_option("--out", args->out, "Write the estimate after each update as TUM");
  cmd.add_option("--plot", args->plot, "Draw map, ground truth, estimate and particle clouds as PNG");
  cmd.add_option("--csv", args->csv, "Per-frame estimate (and errors, with ground truth) as CSV");
  addLiveOptions(cmd, args->live);
  cmd.add_flag("--json", args->json, "Print one JSON object (frames, updates, updates_per_s, wall_s, accuracy, counters)");
  cmd.callback([args] { runLocalize(*args); });
}

}  // namespace polyloc::cli
