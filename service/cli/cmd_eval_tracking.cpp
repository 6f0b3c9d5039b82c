// polyloc eval tracking: people-tracking quality on a simulated run of a scenario
// (kernels/eval/tracking_quality.hpp): motion detection and Kalman tracking on its level planar
// scanners, scored with CLEAR-MOT against the people walking in it. A summary (or --json) on
// stdout, progress on stderr when it is a terminal; --plot draws tracks against the truth.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "viz/tracking_plot.hpp"

#include <polyloc/eval/tracking_quality.hpp>
#include <polyloc/sim/simulator.hpp>
#include <polyloc/tracking/config_yaml.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>

namespace polyloc::cli {
namespace cmd_eval_tracking_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct Args {
  std::string scenario, plot, tracking;
  TrackingEvalOptions eval;
  int64_t seed = -1;
  bool json = false;
};

nlohmann::json toJson(const MotMetrics& m) {
  return {{"mota", m.mota}, {"motp_m", m.motp_m}, {"track_rmse_m", m.rmse_m},
          {"id_switches", m.id_switches}, {"id_switches_per_100s", m.id_switches_per_100s}, {"reentries", m.reentries},
          {"track_seconds", m.track_seconds}, {"ground_truth", m.ground_truth}, {"matches", m.matches},
          {"misses", m.misses}, {"false_positives", m.false_positives}, {"frames", m.frames}};
}

void plot(const Args& a, const Mesh& map, const TrackingQuality& q) {
  viz::TrackingPlotData d;
  d.people.resize(q.people);
  std::map<uint32_t, size_t> track_index;
  for (const TrackingEvalFrame& f : q.frames) {
    d.robot_path.push_back({float(f.map_T_base.x()), float(f.map_T_base.y())});
    for (const MotObject& o : f.truth) d.people[o.id].push_back({o.position.cast<float>(), o.care});
    for (const TrackState& t : f.tracks) {
      auto [it, fresh] = track_index.try_emplace(t.id, d.tracks.size());
      if (fresh) d.tracks.push_back({t.id, {}});
      d.tracks[it->second].points.push_back(t.position.cast<float>());
    }
  }
  const MotMetrics& m = q.mot;
  d.title = fmt::format("polyloc eval tracking {}{}", std::filesystem::path(a.scenario).filename().string(),
                        a.eval.odometry ? " (odometry poses)" : "");
  d.legend = fmt::format("MOTA {:.3f}, RMSE {:.3f} m, {} id switches ({:.2f} per 100 track-s), {} misses, {} false positives",
                         m.mota, m.rmse_m, m.id_switches, m.id_switches_per_100s, m.misses, m.false_positives);
  if (auto dir = std::filesystem::path(a.plot).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  viz::drawTracking(map, d, a.plot);
}

void run(const Args& a) {
  checkOutputs({{"--scenario", a.scenario}}, {{"--plot", a.plot}});
  Scenario s = loadScenario(a.scenario);
  if (a.seed >= 0) s.seed = uint64_t(a.seed);
  const Mesh map = loadScenarioMap(s);
  TrackingEvalOptions o = a.eval;
  o.keep_frames = !a.plot.empty();
  const bool tty = !a.json && isatty(fileno(stderr));
  auto progress = [&](double f) {
    if (!tty) return;
    fmt::print(stderr, "\reval tracking {} {:3.0f}%", barText(f), 100 * f);
    std::fflush(stderr);
  };
  TrackingConfig config = s.config.tracking;
  if (!a.tracking.empty()) {  // a file with a `tracking:` section instead of the scenario config's
    ConfigMap file = ConfigMap::load(a.tracking);
    config = parseTrackingConfig(file.map("tracking"), &s.config.rig);
    file.finish();
  }
  const TrackingQuality q = evaluateTracking(s, map, config, o, progress);
  if (tty) fmt::print(stderr, "\n");
  if (!a.plot.empty()) plot(a, map, q);
  const MotMetrics& m = q.mot;
  if (a.json) {
    nlohmann::json j = toJson(m);
    j.update({{"scenario", a.scenario}, {"seed", s.seed}, {"odometry", o.odometry}, {"match_distance_m", o.match_distance},
              {"min_beams", o.min_beams}, {"range_m", o.range}, {"min_speed", o.min_speed},
              {"forget_after_s", o.forget_after}, {"people", q.people}, {"sim_duration_s", q.sim_duration_s},
              {"wall_s", q.wall_s}, {"tracking_s", q.tracking_s}, {"scans", q.counters.scans},
              {"rejected_scans", q.counters.rejected}, {"detections", q.counters.detections},
              {"strict", toJson(q.strict)}});
    if (!a.plot.empty()) j["plot"] = a.plot;
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("{}: {} people, {:.1f} s simulated, {} tracking steps, {} detections\n", a.scenario, q.people,
             q.sim_duration_s, q.counters.steps, q.counters.detections);
  fmt::print("MOTA {:.3f}  MOTP {:.3f} m  RMSE {:.3f} m  id switches {} ({:.2f} per 100 track-s, {:.0f} track-s)\n",
             m.mota, m.motp_m, m.rmse_m, m.id_switches, m.id_switches_per_100s, m.track_seconds);
  fmt::print("ground truth {}, matches {}, misses {}, false positives {}, re-entries {}\n", m.ground_truth, m.matches,
             m.misses, m.false_positives, m.reentries);
  fmt::print("strict (standing people count too): MOTA {:.3f}, misses {} of {}\n", q.strict.mota, q.strict.misses,
             q.strict.ground_truth);
  fmt::print("tracking {:.2f} s of {:.2f} s wall\n", q.tracking_s, q.wall_s);
}

}  // namespace cmd_eval_tracking_impl

void registerEvalTracking(CLI::App& eval) {
  using namespace cmd_eval_tracking_impl;
  auto a = std::make_shared<Args>();
  CLI::App& c = *eval.add_subcommand("tracking", "People-tracking quality (CLEAR-MOT) on a simulated run");
  c.add_option("--scenario", a->scenario, "Scenario YAML; its config's tracking: section is used")->required()->check(CLI::ExistingFile);
  c.add_flag("--odometry", a->eval.odometry, "Poses from the simulated wheel odometry instead of the ground truth");
  c.add_option("--tracking", a->tracking, "YAML file whose tracking: section replaces the scenario config's")
      ->check(CLI::ExistingFile);
  addDurationOption(c, a->eval.duration, "Simulated seconds", "the scenario");
  addSeedOption(c, a->seed, "Overrides the scenario's seed");
  c.add_option("--match-distance", a->eval.match_distance, "CLEAR-MOT match threshold, m")->capture_default_str()->check(finiteRange(1e-3, 100.0));
  c.add_option("--min-beams", a->eval.min_beams, "Beams on a person for them to be visible")->capture_default_str()->check(finiteRange(0, 1e6));
  c.add_option("--range", a->eval.range, "m: people only count within this range of a scanner")->capture_default_str()->check(finiteRange(0.0, 1e4));
  c.add_option("--min-speed", a->eval.min_speed, "m/s: slower people are don't-care")->capture_default_str()->check(finiteRange(0.0, 100.0));
  c.add_option("--forget-after", a->eval.forget_after, "s out of view after which a new track is a re-entry, not a switch")
      ->capture_default_str();
  c.add_option("--plot", a->plot, "PNG of tracks against the true paths");
  c.add_flag("--json", a->json, "Metrics as one JSON object on stdout");
  c.callback([a] { run(*a); });
}

}  // namespace polyloc::cli
