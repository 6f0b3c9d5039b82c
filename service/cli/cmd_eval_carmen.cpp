// polyloc eval carmen: localisation on a real log with known poses (reloc/carmen_eval.hpp,
// docs/localization.md "Real logs"): map from the even scans, the odd scans localised with drift
// odometry and with the log's own, the floor the map allows, global localisation from random
// test frames. A summary (or --json) on stdout, progress on stderr when it is a terminal, --plot
// draws the map, the paths and the global starts.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "reloc/carmen_eval.hpp"
#include "reloc/report.hpp"
#include "viz/topview.hpp"

#include <polyloc/eval/stats.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/tum.hpp>
#include <polyloc/map/load.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace polyloc::cli {
namespace {

struct Args {
  reloc::CarmenEvalOptions eval;
  std::string variants = "drift,own", plot, save;
  bool json = false;
};

// Frames farther than this from the truth after convergence: lost, for the table.
constexpr double kLostM = 0.5;
// A test scan leaves the position open along the heading (a corridor) when its alignment's std
// along it exceeds this (m).
constexpr double kOpenAlongM = 0.05;

// The errors of a variant split by what the scans pin down: frames whose scan fixes the position
// in every direction, and frames that leave it open along the heading (corridors).
nlohmann::json splitByObservability(const TrajectoryMetrics& m, const reloc::CarmenEvalResult& r) {
  std::map<int64_t, size_t> index;
  for (size_t k = 0; k < r.truth.size(); ++k) index[r.truth[k].stamp_ns] = k;
  std::vector<FrameError> pinned, open;
  for (const FrameError& f : m.frames) {
    auto it = index.find(f.stamp_ns);
    if (it == index.end() || it->second >= r.floor_std_along.size()) continue;
    (r.floor_std_along[it->second] > kOpenAlongM ? open : pinned).push_back(f);
  }
  auto part = [](const std::vector<FrameError>& v) {
    const ErrorSummary s = summarize(v);
    return nlohmann::json{{"frames", s.frames}, {"ate_rmse_m", reloc::num(s.ate_rmse_m)}, {"p95_pos_err_m", reloc::num(s.p95_pos_err_m)}};
  };
  return {{"pinned", part(pinned)}, {"open_along_heading", part(open)}, {"open_threshold_m", kOpenAlongM}};
}

nlohmann::json headingJson(const TrajectoryMetrics& m) {
  const HeadingSplit h = splitByHeading(m.frames);
  return {{"along_rmse_m", reloc::num(h.along_rmse_m)}, {"across_rmse_m", reloc::num(h.across_rmse_m)}};
}

size_t framesBeyond(const TrajectoryMetrics& m, double d) {
  size_t n = 0;
  for (const auto& f : m.frames) n += f.converged && f.pos_err > d;
  return n;
}

nlohmann::json variantJson(const reloc::CarmenVariant& v, const reloc::CarmenEvalResult& r) {
  const std::optional<TrajectoryMetrics>& floor = r.floor;
  nlohmann::json j = reloc::resultJson(v.job, v.metrics ? &*v.metrics : nullptr);
  j.erase("input");
  j["stamps"] = v.stamps;
  j["odometry_messages"] = v.odometry;
  j["odometry_dropped"] = v.odometry_dropped;
  j["odometry_only"] = reloc::summaryJson(v.odometry_only.all);
  if (!v.unusable.empty()) j["unusable"] = v.unusable;
  if (v.metrics) {
    j["frames_beyond_0_5m_after_convergence"] = framesBeyond(*v.metrics, kLostM);
    if (floor) j["by_observability"] = splitByObservability(*v.metrics, r);
    j["by_heading"] = headingJson(*v.metrics);
    if (floor && floor->all.ate_rmse_m > 0) {
      j["ate_over_floor"] = v.metrics->all.ate_rmse_m / floor->all.ate_rmse_m;
      j["p95_over_floor"] = v.metrics->all.p95_pos_err_m / floor->all.p95_pos_err_m;
    }
  }
  return j;
}

void drawPlot(const Args& a, const reloc::CarmenEvalResult& r) {
  const Eigen::AlignedBox3f b3 = r.mesh.bounds();
  const Eigen::AlignedBox2f b(b3.min().head<2>(), b3.max().head<2>());
  const float extent = std::max(b.sizes().x(), b.sizes().y());
  viz::TopView view(b, std::clamp(3000.f / std::max(extent, 1.f), 2.f, 40.f));
  view.drawMeshSlice(r.mesh, 0.3f, &viz::kGray, 1);
  auto path = [&](const std::vector<Eigen::Vector2f>& p, viz::Color c, int w) {
    for (size_t i = 1; i < p.size(); ++i) view.drawLine(p[i - 1], p[i], c, w);
  };
  auto xy = [](const Pose& p) { return Eigen::Vector2f(float(p.x()), float(p.y())); };
  std::vector<Eigen::Vector2f> truth;
  for (const auto& t : r.truth) truth.push_back(xy(t.pose));
  std::string legend = fmt::format("polyloc eval carmen {}: {} test scans; black truth", std::filesystem::path(r.log).filename().string(), r.test_scans);
  const viz::Color colors[2] = {viz::kBlue, viz::kOrange};
  for (size_t k = 0; k < r.variants.size() && k < 2; ++k) {
    const auto& v = r.variants[k];
    std::vector<Eigen::Vector2f> odo, est;
    for (const auto& f : v.odometry_only.frames) odo.push_back(xy(f.estimate));
    for (const auto& f : v.job.frames) est.push_back(xy(f.pose));
    if (k == 0) path(odo, viz::kGray, 1);
    path(est, colors[k], 2);
    legend += fmt::format(", {} {}", k == 0 ? "blue" : "orange", v.name);
    if (v.metrics) {
      const HeadingSplit h = splitByHeading(v.metrics->frames);
      legend += fmt::format(" (ATE {:.3f} m: {:.3f} along the heading, {:.3f} across)", v.metrics->all.ate_rmse_m,
                            h.along_rmse_m, h.across_rmse_m);
    }
  }
  path(truth, viz::kBlack, 1);
  if (!r.variants.empty()) legend += fmt::format(", grey {} odometry alone", r.variants[0].name);
  size_t ok = 0;
  for (const auto& t : r.global) {
    ok += t.success;
    view.drawPose(t.truth, t.success ? viz::kGreen : viz::kRed, 0.4f);
  }
  if (!r.global.empty()) legend += fmt::format("\nglobal: {}/{} (green) within {} m, {} deg after {} updates", ok, r.global.size(),
                                               a.eval.global_pos_tol, a.eval.global_yaw_tol_deg, a.eval.global_updates);
  if (r.floor) {
    const HeadingSplit h = splitByHeading(r.floor->frames);
    legend += fmt::format("\nfloor (test scans aligned to the map): RMSE {:.3f} m: {:.3f} along the heading, {:.3f} across",
                          r.floor->all.ate_rmse_m, h.along_rmse_m, h.across_rmse_m);
  }
  view.drawLegend(legend);
  view.drawScaleBar();
  if (auto dir = std::filesystem::path(a.plot).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  view.save(a.plot);
}

// The map, the test runs as MCAP, their estimates (TUM, CSV with errors) and a config, so that
// `polyloc localize` reproduces a variant exactly (the command is printed).
void save(const Args& a, const reloc::CarmenEvalResult& r) {
  namespace fs = std::filesystem;
  fs::create_directories(a.save);
  const fs::path dir(a.save);
  saveMesh(r.mesh, (dir / "map.obj").string());
  saveGridMap(r.grid, (dir / "map.yaml").string());
  std::string config = a.eval.config;
  if (config.empty()) {
    config = (dir / "carmen.yaml").string();
    std::ofstream(config) << "# polyloc eval carmen's built-in config\nmap: map.obj\nrobot: {radius: 0.25}\nrig: recorded\n";
  }
  {
    TumWriter truth((dir / "truth.tum").string());
    for (const auto& p : r.truth) truth.write(p);
  }
  if (r.floor) {  // each test scan aligned to the map: the best the map allows
    TumWriter floor((dir / "floor.tum").string());
    for (const auto& f : r.floor->frames) floor.write({f.stamp_ns, f.estimate});
  }
  for (const auto& v : r.variants) {
    const std::string mcap = (dir / (v.name + ".mcap")).string();
    auto w = createMcap(mcap);
    for (const RecordedMessage& m : *v.run) w->write(m.topic, m.log_time_ns, m.message);
    w->close();
    reloc::writeTum((dir / (v.name + ".tum")).string(), v.job.frames);
    reloc::writeCsv((dir / (v.name + ".csv")).string(), v.metrics ? &*v.metrics : nullptr, v.job.frames);
    fmt::print(stderr, "polyloc eval carmen: {} run saved; the same localisation: polyloc localize --input {} --config {} --map {}\n",
               v.name, mcap, config, (dir / "map.obj").string());
  }
}

void run(Args a) {
  checkOutputs({{"--log", a.eval.log}, {"--config", a.eval.config}}, {{"--plot", a.plot}}, {{"--save", a.save}});
  a.eval.variants.clear();
  for (const std::string& v : splitList(a.variants))
    if (v != "none") a.eval.variants.push_back(v);
  a.eval.plot = !a.plot.empty();
  const bool tty = isatty(fileno(stderr));
  auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  if (tty)
    a.eval.progress = [&](const std::string& stage, double f) {
      const auto now = std::chrono::steady_clock::now();
      if (f < 1.0 && now - last < std::chrono::milliseconds(100)) return;
      last = now;
      fmt::print(stderr, "\reval carmen {:>6} {} {:3.0f}%", stage, barText(f, 30), 100 * f);
      std::fflush(stderr);
    };
  a.eval.log_line = [tty](const std::string& s) { fmt::print(stderr, "{}polyloc eval carmen: {}\n", tty ? "\r\033[K" : "", s); };
  const reloc::CarmenEvalResult r = reloc::runCarmenEval(a.eval);
  if (tty) fmt::print(stderr, "\r\033[K");
  if (!a.plot.empty()) drawPlot(a, r);
  if (!a.save.empty()) save(a, r);

  size_t ok = 0;
  std::vector<double> first;
  double global_s = 0;
  for (const auto& t : r.global) {
    ok += t.success, global_s += t.filter_s;
    if (t.success) first.push_back(t.first_within);
  }
  if (a.json) {
    nlohmann::json j = {{"log", r.log}, {"topic", r.topic}, {"geometry", r.geometry}, {"scans", r.scans},
                        {"map_scans", r.map_scans}, {"test_scans", r.test_scans}, {"log_odometry", r.log_odometry},
                        {"config", r.config.file}, {"seed", a.eval.seed}, {"wall_s", r.wall_s}};
    j["map"] = {{"cells_x", r.grid.width}, {"cells_y", r.grid.height}, {"resolution_m", r.grid.resolution},
                {"triangles", r.mesh.numTriangles()}, {"build_s", r.map_s}};
    if (r.floor) {
      j["floor"] = reloc::summaryJson(r.floor->all);
      j["floor"]["refined"] = r.floor_refined;
      j["floor"]["refused"] = r.floor_refused;
      j["floor"]["by_observability"] = splitByObservability(*r.floor, r);
      j["floor"]["by_heading"] = headingJson(*r.floor);
      auto pct = [](const std::vector<double>& v) {
        return nlohmann::json{{"p01", percentile(v, 1)}, {"p05", percentile(v, 5)}, {"p50", percentile(v, 50)}, {"p95", percentile(v, 95)}, {"max", percentile(v, 100)}};
      };
      j["fit_check"] = {{"aligned", pct(r.seen_through_aligned)}, {"displaced_0_5m", pct(r.seen_through_0_5m)},
                        {"displaced_2m", pct(r.seen_through_2m)}, {"explained_aligned", pct(r.explained_aligned)}};
      j["floor"]["seconds"] = r.floor_s;
    }
    nlohmann::json vs = nlohmann::json::object();
    for (const auto& v : r.variants) vs[v.name] = variantJson(v, r);
    j["variants"] = vs;
    nlohmann::json g = nlohmann::json::array();
    for (const auto& t : r.global)
      g.push_back({{"start", t.test_index}, {"success", t.success}, {"updates", t.updates}, {"first_within", t.first_within},
                   {"pos_err_m", t.pos_err}, {"yaw_err_deg", t.yaw_err_deg}});
    j["global"] = {{"trials", r.global.size()}, {"succeeded", ok}, {"fraction", r.global.empty() ? 0.0 : double(ok) / double(r.global.size())},
                   {"updates", a.eval.global_updates}, {"pos_tol_m", a.eval.global_pos_tol}, {"yaw_tol_deg", a.eval.global_yaw_tol_deg},
                   {"median_first_within", first.empty() ? nlohmann::json(nullptr) : nlohmann::json(percentile(first, 50))},
                   {"filter_s", global_s}, {"results", g}};
    if (!a.plot.empty()) j["plot"] = a.plot;
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("log        {}: {} scans on {} ({}), {} ODOM messages\n", r.log, r.scans, r.topic, r.geometry, r.log_odometry);
  fmt::print("map        {} even scans -> {} x {} cells at {} m -> {} triangles ({:.1f} s)\n", r.map_scans, r.grid.width,
             r.grid.height, r.grid.resolution, r.mesh.numTriangles(), r.map_s);
  if (r.floor)
    fmt::print("floor      {} test scans aligned to the map: RMSE {:.3f} m, p95 {:.3f} m, yaw RMSE {:.2f} deg, p95 {:.2f} deg ({:.1f} s)\n",
               r.floor->all.frames, r.floor->all.ate_rmse_m, r.floor->all.p95_pos_err_m, r.floor->all.yaw_rmse_deg,
               r.floor->all.p95_yaw_err_deg, r.floor_s);
  for (const auto& v : r.variants) {
    const double ups = v.job.filter_s > 0 ? double(v.job.updates) / v.job.filter_s : 0.0;
    if (!v.unusable.empty()) {
      fmt::print("{:<10} not localised: {}\n", v.name, v.unusable);
      continue;
    }
    if (!v.metrics) {
      fmt::print("{:<10} no estimate could be evaluated\n", v.name);
      continue;
    }
    const auto& s = v.metrics->all;
    fmt::print("{:<10} ATE {:.3f} m{}, p95 {:.3f} m, p95 yaw {:.2f} deg, worst {:.3f} m, {} frames beyond {} m after convergence, "
               "{} relocalisations, {:.1f} updates/s; odometry alone ATE {:.3f} m, p95 {:.3f} m ({} odometry messages{}; stamps {})\n",
               v.name, s.ate_rmse_m, r.floor ? fmt::format(" ({:.2f}x floor)", s.ate_rmse_m / r.floor->all.ate_rmse_m) : "",
               s.p95_pos_err_m, s.p95_yaw_err_deg, s.max_pos_err_m, framesBeyond(*v.metrics, kLostM), kLostM,
               v.job.counters.at("relocalizations"), ups, v.odometry_only.all.ate_rmse_m, v.odometry_only.all.p95_pos_err_m,
               v.odometry, v.odometry_dropped ? fmt::format(", {} copies of logged poses dropped", v.odometry_dropped) : "",
               v.stamps);
  }
  if (!r.global.empty())
    fmt::print("global     {}/{} random test frames within {} m and {} deg after {} updates (median first within: {})\n", ok,
               r.global.size(), a.eval.global_pos_tol, a.eval.global_yaw_tol_deg, a.eval.global_updates,
               first.empty() ? -1.0 : percentile(first, 50));
  if (!a.plot.empty()) fmt::print("plot       {}\n", a.plot);
}

}  // namespace

void registerEvalCarmen(CLI::App& eval) {
  auto a = std::make_shared<Args>();
  CLI::App& c = *eval.add_subcommand("carmen", "Localisation on a real CARMEN log with corrected poses: map from the even scans, odd scans localised");
  c.add_option("--log", a->eval.log, "CARMEN log with corrected poses (.log, .gz)")->required()->check(CLI::ExistingFile);
  c.add_option("--config", a->eval.config, "polyloc config (its map is ignored; default: robot.radius 0.25, rig recorded, mcl defaults)");
  c.add_option("--topic", a->eval.topic, "Scan topic (default: the log's first laser with poses)");
  c.add_option("--variants", a->variants, "Test runs: drift (corrected path + seeded drift), own (the log's ODOM), or none (global trials only)")->capture_default_str();
  c.add_option("--every", a->eval.every, "Keep every N/2-th of the odd scans as test scans (2: all)")->capture_default_str()->check(finiteRange(2, 100000));
  c.add_option("--drift", a->eval.drift.translation, "Drift odometry: translation error std per metre (fraction)")->capture_default_str()->check(finiteRange(0.0, 10.0));
  addSeedOption(c, a->eval.seed, "Seed of the drift and the global starts")->capture_default_str();
  c.add_option("--resolution", a->eval.mapper.resolution, "Map grid cell size, m")->capture_default_str()->check(finiteRange(0.005, 1.0));
  c.add_option("--global-trials", a->eval.global_trials, "Global localisation trials (0: none)")->capture_default_str()->check(finiteRange(0, 10000));
  c.add_option("--global-updates", a->eval.global_updates, "Updates after which a global trial must be within tolerance")->capture_default_str()->check(finiteRange(1, 100000));
  c.add_option("--restamp", a->eval.restamp_hz, "Rate at which runs whose stamps do not increase are restamped by order (Hz)")->capture_default_str()->check(finiteRange(1e-3, 1e9));
  c.add_flag("--no-floor", [a](int64_t) { a->eval.floor = false; }, "Skip the floor (alignment of every test scan)");
  c.add_option("--plot", a->plot, "PNG of the map, truth, estimates, odometry and global starts");
  c.add_option("--save", a->save, "Folder for the map (OBJ, grid), the test runs (MCAP), their estimates (TUM, CSV) and the truth");
  c.add_flag("--json", a->json, "Summary as one JSON object on stdout");
  c.callback([a] { run(*a); });
}

}  // namespace polyloc::cli
