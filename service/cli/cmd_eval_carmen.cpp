// polyloc eval carmen: localisation on a real log with known poses (reloc/carmen_eval.hpp,
// docs/localization.md "Real logs"): maps from the even scans in one or more styles, the odd
// scans localised with drift odometry of one or more levels at one or more decimations (the
// robustness matrix) and with the log's own, the floor each map allows, global localisation from
// random test frames. A table (or --json) on stdout, progress on stderr when it is a terminal,
// --plot draws the map, the paths and the global starts, --strips the error of every case.
#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/output_check.hpp"
#include "cli/parse_number.hpp"
#include "cli/progress_bar.hpp"
#include "reloc/carmen_eval.hpp"
#include "reloc/carmen_report.hpp"
#include "reloc/report.hpp"

#include <polyloc/io/recording.hpp>
#include <polyloc/io/tum.hpp>
#include <polyloc/map/load.hpp>

#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace polyloc::cli {
namespace cmd_eval_carmen_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct Args {
  reloc::CarmenEvalOptions eval;
  std::string map_styles = "polyloc", drifts = "mid", decimations = "1", plot, strips, save;
  bool matrix = false, no_own = false, json = false;
};

// The maps (OBJ, grid), each case's run as MCAP with its estimates (TUM, CSV) and the truth,
// and a config, so that `polyloc localize` reproduces a case exactly (the command is printed).
void save(const Args& a, const reloc::CarmenEvalResult& r) {
  namespace fs = std::filesystem;
  const fs::path dir(a.save);
  fs::create_directories(dir);
  std::string config = a.eval.config;
  if (config.empty()) {
    config = (dir / "carmen.yaml").string();
    std::ofstream(config) << "# polyloc eval carmen's built-in config (its map: --map)\nrobot: {radius: 0.25}\nrig: recorded\n";
  }
  {
    TumWriter truth((dir / "truth.tum").string());
    for (const auto& p : r.truth) truth.write(p);
  }
  for (const auto& m : r.maps) {
    const fs::path md = dir / m.map.style;
    fs::create_directories(md);
    saveMesh(m.map.mesh, (md / "map.obj").string());
    saveGridMap(m.map.grid, (md / "map.yaml").string());
    if (m.floor) {  // each test scan aligned to the map: the best the map allows
      TumWriter floor((md / "floor.tum").string());
      for (const auto& f : m.floor->frames) floor.write({f.stamp_ns, f.estimate});
    }
  }
  for (const auto& c : r.cases) {
    std::string stem = c.name();
    std::replace(stem.begin(), stem.end(), '/', '_');
    const std::string mcap = (dir / (stem + ".mcap")).string();
    auto w = createMcap(mcap);
    for (const RecordedMessage& m : *c.run) w->write(m.topic, m.log_time_ns, m.message);
    w->close();
    if (!c.unusable.empty()) continue;
    reloc::writeTum((dir / (stem + ".tum")).string(), c.job.frames);
    reloc::writeCsv((dir / (stem + ".csv")).string(), c.metrics ? &*c.metrics : nullptr, c.job.frames);
    fmt::print(stderr, "polyloc eval carmen: {} saved; the same localisation: polyloc localize --input {} --config {} --map {}\n",
               c.name(), mcap, config, (dir / c.map_style / "map.obj").string());
  }
}

void run(Args a) {
  checkOutputs({{"--log", a.eval.log}, {"--config", a.eval.config}}, {{"--plot", a.plot}, {"--strips", a.strips}}, {{"--save", a.save}});
  if (a.matrix) a.map_styles = fmt::format("{}", fmt::join(logMapStyles(), ",")), a.drifts = "low,mid,high,slip", a.decimations = "1,2,4";
  a.eval.map_styles = splitList(a.map_styles);
  a.eval.drifts.clear();
  for (const std::string& d : splitList(a.drifts))
    if (d != "none") a.eval.drifts.push_back(parseDrift(d));
  a.eval.decimations.clear();
  for (double d : parseNumbers(a.decimations, "--decimate")) {
    if (d < 1 || d > 1000 || d != std::floor(d)) throw std::runtime_error(fmt::format("--decimate: {} is not a whole number in 1..1000", d));
    a.eval.decimations.push_back(size_t(d));
  }
  a.eval.own = !a.no_own;
  a.eval.plot = !a.plot.empty();
  const bool tty = isatty(fileno(stderr));
  auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  if (tty)
    a.eval.progress = [&](const std::string& stage, double f) {
      const auto now = std::chrono::steady_clock::now();
      if (f < 1.0 && now - last < std::chrono::milliseconds(100)) return;
      last = now;
      fmt::print(stderr, "\r\033[Keval carmen {:<22} {} {:3.0f}%", stage, barText(f, 30), 100 * f);
      std::fflush(stderr);
    };
  a.eval.log_line = [tty](const std::string& s) { fmt::print(stderr, "{}polyloc eval carmen: {}\n", tty ? "\r\033[K" : "", s); };
  const reloc::CarmenEvalResult r = reloc::runCarmenEval(a.eval);
  if (tty) fmt::print(stderr, "\r\033[K");
  if (!a.plot.empty()) reloc::drawCarmenPlot(r, a.eval, a.plot);
  if (!a.strips.empty()) reloc::drawCarmenStrips(r, a.strips);
  if (!a.save.empty()) save(a, r);
  if (a.json) {
    nlohmann::json j = reloc::carmenJson(r, a.eval);
    if (!a.plot.empty()) j["plot"] = a.plot;
    if (!a.strips.empty()) j["strips"] = a.strips;
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("{}", reloc::carmenText(r, a.eval));
  if (!a.plot.empty()) fmt::print("plot       {}\n", a.plot);
  if (!a.strips.empty()) fmt::print("strips     {}\n", a.strips);
}

}  // namespace cmd_eval_carmen_impl

void registerEvalCarmen(CLI::App& eval) {
  using namespace cmd_eval_carmen_impl;
  auto a = std::make_shared<Args>();
  CLI::App& c = *eval.add_subcommand("carmen", "Localisation on a real CARMEN log with corrected poses: maps from the even scans, odd scans localised");
  c.add_option("--log", a->eval.log, "CARMEN log with corrected poses (.log, .gz)")->required()->check(CLI::ExistingFile);
  c.add_option("--config", a->eval.config, "polyloc config (its map is ignored; default: robot.radius 0.25, rig recorded, mcl defaults)");
  c.add_option("--topic", a->eval.topic, "Scan topic (default: the log's first laser with poses)");
  std::string styles;
  for (const std::string& s : logMapStyles()) styles += fmt::format("\n  {}: {}", s, describeLogMapStyle(s));
  c.add_option("--map-styles", a->map_styles, "Maps built from the even scans, comma-separated:" + styles)->capture_default_str();
  c.add_option("--drift", a->drifts, "Drift odometries, comma-separated: low (2 %, 0.5 deg/m), mid (5 %, 1 deg/m), high (10 %, 2 deg/m), "
               "slip (mid + a 10-30 cm / 5-10 deg slip every 10 m), P/D (P % and D deg per m), +slip after any; none: only the log's own")
      ->capture_default_str();
  c.add_option("--decimate", a->decimations, "Test scans used, comma-separated: 1 every one, 2 every 2nd, 4 every 4th ...")->capture_default_str();
  c.add_flag("--matrix", a->matrix, "The whole robustness matrix: every map style x low,mid,high,slip x 1,2,4");
  c.add_flag("--no-own", a->no_own, "Skip the run with the log's own ODOM lines");
  c.add_option("--test-scans", a->eval.test_scans, "Only the first N test scans (0: all)")->capture_default_str()->check(finiteRange(0, 1e9));
  addSeedOption(c, a->eval.seed, "Seed of the drift, the noisy map and the global starts")->capture_default_str();
  c.add_option("--resolution", a->eval.map.resolution, "Map grid cell size, m (coarse: twice this)")->capture_default_str()->check(finiteRange(0.005, 1.0));
  c.add_option("--global-trials", a->eval.global_trials, "Global localisation trials per map style (0: none)")->capture_default_str()->check(finiteRange(0, 10000));
  c.add_option("--global-updates", a->eval.global_updates, "Updates after which a global trial must be within tolerance")->capture_default_str()->check(finiteRange(1, 100000));
  c.add_option("--restamp", a->eval.restamp_hz, "Rate at which runs whose stamps do not increase are restamped by order (Hz)")->capture_default_str()->check(finiteRange(1e-3, 1e9));
  c.add_flag("--no-floor", [a](int64_t) { a->eval.floor = false; }, "Skip the floor (alignment of every test scan)");
  c.add_option("--plot", a->plot, "PNG of the first map, truth, estimates, odometry and global starts");
  c.add_option("--strips", a->strips, "PNG grid of error-over-time strips, one per case (rows map style x decimation, columns odometry)");
  c.add_option("--save", a->save, "Folder for the maps (OBJ, grid), each case's run (MCAP), estimates (TUM, CSV) and the truth");
  c.add_flag("--json", a->json, "Summary as one JSON object on stdout");
  c.callback([a] { run(*a); });
}

}  // namespace polyloc::cli
