// polyloc play: the stand-in for a robot. Feeds a recording (MCAP, ROS 2 bag, CARMEN) or a
// scenario simulated live into a polylocd instance's input channels at real time (or --rate X),
// restamped to the wall clock, and watches what comes back: pose (error against the ground
// truth the source carries), latency from scan to pose, rates, and what polylocd dropped or
// rejected. Status on stderr; a summary (--json) on stdout; --plot draws the trajectories.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "reloc/report.hpp"
#include "engines/play_feed.hpp"
#include "cli/play_source.hpp"
#include "cli/play_drive.hpp"
#include "cli/live_option.hpp"
#include "viz/localize_plot.hpp"

#include <polyloc/eval/stats.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>
#include <polyloc/io/tum.hpp>
#include <polyloc/map/load.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <thread>

namespace polyloc::cli {

using engines::PlayFeed;
using engines::PlayResult;
namespace cmd_play_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

using Clock = std::chrono::steady_clock;

struct PlayArgs {
  std::string input, scenario, shm, plot, map, truth;
  double rate = 1.0, duration = 0, wait = 10, command_latency = 0.05;
  bool json = false, quiet = false, loop = false, drive = false;
  LiveArgs live;
};

void runPlay(const PlayArgs& a) {
  if (a.drive) {
    if (a.scenario.empty()) throw std::runtime_error("--drive needs --scenario FILE (a recording cannot be driven)");
    if (a.loop || !a.plot.empty() || !a.truth.empty() || a.live.port)
      throw std::runtime_error("--drive does not take --loop, --plot, --truth or --live (polylocd serves its live view)");
    runPlayDrive({a.scenario, a.shm, a.rate, a.duration, a.wait, a.command_latency, a.json, a.quiet});
    return;
  }
  if (a.input.empty() == a.scenario.empty()) throw std::runtime_error("give --input RUN or --scenario FILE (one of them)");
  if (!(a.rate > 0)) throw std::runtime_error("--rate must be > 0");
  checkOutputs({{"--input", a.input}, {"--scenario", a.scenario}, {"--map", a.map}}, {{"--plot", a.plot}, {"--truth", a.truth}});
  std::optional<TumWriter> truth_out;  // opened now: a bad path fails before the run, not after it
  if (!a.truth.empty()) truth_out.emplace(a.truth);
  std::unique_ptr<PlaySource> src = a.input.empty() ? playScenario(a.scenario, a.duration) : playRecording(a.input);
  // --live: polylocd's poses beside the source's truth, on the map (the scans are polylocd's view).
  std::optional<Mesh> live_map;
  if (a.live.port && !src->map()) {
    if (a.map.empty()) throw std::runtime_error("--live needs --map MESH when playing a recording");
    live_map = loadMesh(a.map);
  }
  PlayFeed feed(a.shm, a.wait);
  if (a.rate != 1.0)
    fmt::print(stderr, "polyloc play: rate {}: stamps keep the data's own pace; polylocd needs `clock: source` "
                       "to accept them (docs/polylocd.md)\n", a.rate);
  const bool tty = isatty(fileno(stderr));
  const double span = a.duration > 0 ? (a.loop ? a.duration : std::min(a.duration, src->durationS())) : src->durationS();

  if (a.loop && !(a.duration > 0)) throw std::runtime_error("--loop needs --duration");
  const Rig no_rig;
  LiveHook live(a.live, src->map() ? *src->map() : *live_map, no_rig, true);
  if (live.on()) {
    feed.on_pose = [&live](const polyloc_pose& p) { live.published(p); };
    feed.on_truth = [&live](int64_t t, const Pose& p) { live.truth(t, p); };
  }
  RecordedMessage m;
  std::optional<int64_t> first;
  int64_t offset = 0, last = 0;  // --loop: each pass continues where the last one ended
  uint64_t passes = 1;
  const auto t0 = Clock::now();
  auto last_status = t0;
  for (;;) {
    if (!src->next(m)) {
      if (!a.loop || !first) break;
      src = a.input.empty() ? playScenario(a.scenario, a.duration) : playRecording(a.input);
      if (!src->next(m)) break;
      offset = last + 100'000'000 - m.log_time_ns;  // 0.1 s after the last message
      ++passes;
    }
    m.log_time_ns += offset;
    last = m.log_time_ns;
    if (!first) first = m.log_time_ns;
    const double t = double(m.log_time_ns - *first) * 1e-9;
    if (a.duration > 0 && t > a.duration) break;
    const auto due = t0 + std::chrono::nanoseconds(int64_t(double(m.log_time_ns - *first) / a.rate));
    // Poll what comes back while waiting for the message's time.
    while (Clock::now() < due) {
      feed.poll();
      std::this_thread::sleep_until(std::min(due, Clock::now() + std::chrono::milliseconds(2)));
    }
    if (Clock::now() - due > std::chrono::milliseconds(100)) feed.countLate();
    feed.send(m, offset, *first);
    feed.poll();
    if (!a.quiet && Clock::now() - last_status > std::chrono::milliseconds(tty ? 250 : 5000)) {
      last_status = Clock::now();
      fmt::print(stderr, "{}{}{}", tty ? "\r" : "", feed.statusLine(t, span), tty ? "\033[K" : "\n");
      std::fflush(stderr);
    }
  }
  feed.finish();  // the last poses and health
  live.finish();
  if (!a.quiet && tty) fmt::print(stderr, "\n");

  const PlayResult r = feed.result();
  std::optional<TrajectoryMetrics> metrics;
  if (!r.truth.empty() && !r.estimates.empty()) metrics = evaluateTrajectory(r.estimates, GroundTruth(r.truth), {});
  if (truth_out) {
    for (const StampedPose& p : r.truth) truth_out->write(p);
    truth_out->close();
  }
  if (!a.plot.empty()) {
    Mesh loaded;
    const Mesh* map = src->map();
    if (!map && !a.map.empty()) loaded = loadMesh(a.map), map = &loaded;
    if (!map) throw std::runtime_error("--plot needs --map MESH when playing a recording");
    viz::LocalizePlotData plot;
    for (const auto& p : r.truth) plot.truth_path.emplace_back(float(p.pose.x()), float(p.pose.y()));
    for (const auto& e : r.estimates) plot.estimate_path.emplace_back(float(e.pose.x()), float(e.pose.y()));
    plot.title = fmt::format("polyloc play {} -> polylocd '{}': {} poses", src->describe(), a.shm, r.estimates.size());
    if (metrics)
      plot.legend = fmt::format("ATE {:.3f} m, p95 {:.3f} m, yaw RMSE {:.2f} deg; latency p50 {:.2f} ms, p99 {:.2f} ms",
                                metrics->all.ate_rmse_m, metrics->all.p95_pos_err_m, metrics->all.yaw_rmse_deg,
                                r.latency_p50_ms, r.latency_p99_ms);
    viz::drawLocalization(*map, plot, a.plot);
  }
  nlohmann::json j = feed.resultJson();
  j["source"] = src->describe();
  j["rate"] = a.rate;
  j["passes"] = passes;
  j["wall_s"] = std::chrono::duration<double>(Clock::now() - t0).count();
  if (metrics) {
    j["accuracy"] = reloc::summaryJson(metrics->all);
    j["converged_after_s"] = metrics->converged_after_s ? reloc::num(*metrics->converged_after_s) : nlohmann::json(nullptr);
  }
  if (!a.plot.empty()) j["plot"] = a.plot;
  if (a.json) fmt::print("{}\n", j.dump());
  else
    fmt::print("play: {} messages sent, {} poses back, latency p50 {:.2f} ms p99 {:.2f} ms, {} frames dropped, {} rejected{}\n",
               r.sent, r.estimates.size(), r.latency_p50_ms, r.latency_p99_ms, r.dropped, r.rejected,
               metrics ? fmt::format(", ATE {:.3f} m", metrics->all.ate_rmse_m) : std::string());
  // The summary is printed either way; the exit status says whether polylocd took part.
  if (!r.answered)
    throw std::runtime_error(fmt::format("polylocd '{}' never answered: no pose and no health frame came back "
                                         "(is it running and reading this segment? its log says why)", a.shm));
  if (!r.up_at_end)
    throw std::runtime_error(fmt::format("polylocd '{}' stopped during the run: {} messages were not delivered",
                                         a.shm, r.undelivered));
}

}  // namespace cmd_play_impl

void registerPlay(CLI::App& app) {
  using namespace cmd_play_impl;
  auto a = std::make_shared<PlayArgs>();
  CLI::App* c = app.add_subcommand("play", "Feed a recording or a live simulation into polylocd's shared memory, and watch the results");
  c->add_option("--input", a->input, "Recording: MCAP, ROS 2 bag, CARMEN log, TUM RGB-D or 7-Scenes folder")->check(CLI::ExistingPath);
  c->add_option("--scenario", a->scenario, "Scenario (maps/scenarios/*.yaml), simulated live")->check(CLI::ExistingFile);
  c->add_option("--shm", a->shm, "polylocd instance (segment /polyloc.NAME)")->required();
  c->add_option("--rate", a->rate, "Playback speed (1: real time)")->capture_default_str()->check(finiteRange(1e-3, 1e3));
  addDurationOption(*c, a->duration, "Seconds of the source to play", "the source");
  c->add_option("--wait", a->wait, "s to wait for polylocd's segment to appear")->capture_default_str()->check(finiteRange(0.0, 3600.0));
  c->add_option("--plot", a->plot, "PNG of map, ground truth and the poses polylocd published");
  addMapOption(*c, a->map, "Mesh for --plot when playing a recording");
  c->add_option("--truth", a->truth, "TUM file of the source's ground truth, stamped as fed (to compare what viewers got)");
  c->add_flag("--drive", a->drive, "Closed loop: the robot executes the velocity commands on polylocd's cmd_vel channel "
                                    "instead of the scenario's route, in lockstep with polylocd and the controller "
                                    "(polylocd needs `clock: source` unless --rate 1; docs/navigation.md)");
  c->add_option("--command-latency", a->command_latency, "s from a command's stamp to the base acting on it (--drive)")
      ->capture_default_str()->check(finiteRange(0.0, 1.0));
  addLiveOptions(*c, a->live, false);  // play paces with --rate
  c->add_flag("--loop", a->loop, "Start the source again at its end, until --duration (soak tests)");
  c->add_flag("--quiet", a->quiet, "No status line");
  c->add_flag("--json", a->json, "Summary as one JSON object on stdout");
  c->callback([a] { runPlay(*a); });
}

}  // namespace polyloc::cli
