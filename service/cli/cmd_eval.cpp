// polyloc eval global|kidnap: repeated localisation trials on simulated drives of a scenario's
// robot (kernels/eval/localization_trials.hpp) — the share of random starts found from a uniform
// prior within a number of rounds, and of kidnappings recovered. Progress on stderr when it is a
// terminal; a summary (or --json) on stdout; --plot draws the starts on the map, green when the
// trial succeeded.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "viz/topview.hpp"

#include <polyloc/eval/localization_trials.hpp>
#include <polyloc/eval/stats.hpp>
#include <polyloc/sim/simulator.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace polyloc::cli {
namespace cmd_eval_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct EvalArgs {
  std::string scenario, plot;
  TrialOptions trials;
  int64_t particles = 0;   // global_particles override (global), 0: the config's
  double yaw_tol_deg = 5;
  bool json = false;
};

void runEval(const EvalArgs& a, bool kidnap) {
  checkOutputs({{"--scenario", a.scenario}}, {{"--plot", a.plot}});
  Scenario s = loadScenario(a.scenario);
  MclConfig mcl = s.config.mcl;
  if (a.particles > 0) mcl.global_particles = size_t(a.particles);
  TrialOptions o = a.trials;
  o.yaw_tol = deg2rad(a.yaw_tol_deg);
  const Mesh map = loadScenarioMap(s);
  const bool tty = !a.json && isatty(fileno(stderr));
  const char* what = kidnap ? "kidnap" : "global";
  auto progress = [&](size_t done, size_t total) {
    if (!tty) return;
    fmt::print(stderr, "\reval {} {} {}/{} trials", what, barText(double(done) / double(std::max<size_t>(total, 1))), done, total);
    std::fflush(stderr);
  };
  const std::vector<TrialResult> r =
      kidnap ? runKidnapTrials(s, map, mcl, o, progress) : runGlobalTrials(s, map, mcl, o, progress);
  if (tty) fmt::print(stderr, "\n");

  size_t ok = 0;
  std::vector<double> rounds, filter_s;
  uint64_t updates = 0;
  double filter_total = 0;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& t : r) {
    ok += t.converged;
    if (t.converged) rounds.push_back(t.converged_round);
    updates += t.updates, filter_total += t.filter_s;
    list.push_back({{"start", {t.start.x(), t.start.y(), rad2deg(t.start.yaw())}},
                    {"converged", t.converged},
                    {"converged_round", t.converged_round},
                    {"final_pos_err_m", t.pos_err.empty() ? -1.0 : t.pos_err.back()},
                    {"final_yaw_err_deg", t.yaw_err.empty() ? -1.0 : rad2deg(t.yaw_err.back())},
                    {"rounds", t.pos_err.size()},
                    {"injected", t.injected}});
  }
  std::sort(rounds.begin(), rounds.end());
  const double frac = r.empty() ? 0.0 : double(ok) / double(r.size());
  const double median = rounds.empty() ? -1 : rounds[rounds.size() / 2];
  const double worst = rounds.empty() ? -1 : rounds.back();

  if (!a.plot.empty()) {
    Eigen::AlignedBox2f b;
    for (const auto& v : map.vertices) b.extend(Eigen::Vector2f(v.x(), v.y()));
    viz::TopView view(b);
    view.drawMeshSlice(map, 0.3f);
    for (const auto& t : r) view.drawPose(t.start, t.converged ? viz::kGreen : viz::kRed, 0.25f);
    view.drawLegend(fmt::format("polyloc eval {} {}: {}/{} within {} m, {} deg in {} rounds (median {}, worst {})", what,
                                std::filesystem::path(a.scenario).filename().string(), ok, r.size(), o.pos_tol,
                                a.yaw_tol_deg, o.rounds, median, worst));
    view.drawScaleBar();
    if (auto dir = std::filesystem::path(a.plot).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    view.save(a.plot);
  }
  const double ups = filter_total > 0 ? double(updates) / filter_total : 0.0;
  if (a.json) {
    nlohmann::json j = {{"mode", what}, {"scenario", a.scenario}, {"trials", r.size()}, {"succeeded", ok},
                        {"fraction", frac}, {"rounds_allowed", o.rounds}, {"hold_rounds", o.hold_rounds},
                        {"pos_tol_m", o.pos_tol}, {"yaw_tol_deg", a.yaw_tol_deg},
                        {"median_rounds", median}, {"worst_rounds", worst}, {"updates_per_s", ups},
                        {"particles", kidnap ? mcl.particles : mcl.global_particles}, {"results", list}};
    if (kidnap) j["kidnap_after_rounds"] = o.kidnap_after;
    if (!a.plot.empty()) j["plot"] = a.plot;
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("{} trials: {}/{} ({:.0f}%) within {} m and {} deg in at most {} rounds (held {} more)\n", what, ok,
             r.size(), 100 * frac, o.pos_tol, a.yaw_tol_deg, o.rounds, o.hold_rounds);
  fmt::print("rounds to converge: median {}, worst {}; {:.1f} updates/s\n", median, worst, ups);
  for (const auto& t : r)
    if (!t.converged)
      fmt::print("  failed: start ({:.2f}, {:.2f}, {:.0f} deg), final error {:.2f} m, {:.1f} deg\n", t.start.x(),
                 t.start.y(), rad2deg(t.start.yaw()), t.pos_err.empty() ? -1.0 : t.pos_err.back(),
                 t.yaw_err.empty() ? -1.0 : rad2deg(t.yaw_err.back()));
}

void addOptions(CLI::App& c, EvalArgs& a, bool kidnap) {
  c.add_option("--scenario", a.scenario, "Scenario YAML: map, rig, noise and people of the drives")->required()->check(CLI::ExistingFile);
  c.add_option("--trials", a.trials.trials, "Number of trials")->capture_default_str()->check(finiteRange(1, 100000));
  c.add_option("--rounds", a.trials.rounds, kidnap ? "Rounds allowed to recover" : "Rounds allowed to converge")
      ->capture_default_str()->check(finiteRange(1, 100000));
  c.add_option("--hold", a.trials.hold_rounds, "Rounds the error must then stay within tolerance")->capture_default_str();
  c.add_option("--pos-tol", a.trials.pos_tol, "Position tolerance, m")->capture_default_str();
  c.add_option("--yaw-tol", a.yaw_tol_deg, "Yaw tolerance, degrees")->capture_default_str();
  addSeedOption(c, a.trials.seed, "Seed of the start poses and routes")->capture_default_str();
  c.add_option("--route-length", a.trials.route_length, "Upper bound of each drive, m")->capture_default_str();
  if (kidnap) c.add_option("--kidnap-after", a.trials.kidnap_after, "Rounds tracked before the kidnapping")->capture_default_str();
  else c.add_option("--global-particles", a.particles, "Particles of the uniform prior (default: mcl.global_particles)")->check(finiteRange(1, 1e8));
  c.add_option("--plot", a.plot, "PNG of the map with the starts (green: succeeded)");
  c.add_flag("--json", a.json, "Summary as one JSON object on stdout");
}

}  // namespace cmd_eval_impl

void registerEval(CLI::App& app) {
  using namespace cmd_eval_impl;
  CLI::App& eval = *app.add_subcommand("eval", "Trials on simulated runs (global localisation, kidnapping, people tracking, depth filtering) and on real logs (carmen)");
  eval.require_subcommand(1);
  auto g = std::make_shared<EvalArgs>();
  CLI::App& global = *eval.add_subcommand("global", "Global localisation from a uniform prior at random starts");
  addOptions(global, *g, false);
  global.callback([g] { runEval(*g, false); });
  auto k = std::make_shared<EvalArgs>();
  k->trials.trials = 20;
  k->trials.rounds = 50;
  CLI::App& kidnap = *eval.add_subcommand("kidnap", "Recovery after the robot is carried elsewhere mid-run");
  addOptions(kidnap, *k, true);
  kidnap.callback([k] { runEval(*k, true); });
  registerEvalTracking(eval);
  registerEvalDepth(eval);
  registerEvalCarmen(eval);
  registerEvalRgbd(eval);
  registerEvalNav(eval);
}

}  // namespace polyloc::cli
