// polyloc eval depth: the depth filter against the tagged artefacts of a simulated run
// (kernels/eval/depth_quality.hpp): the share of outlier pixels (flying pixels, reflection
// outliers) removed and of valid pixels kept, combined and per filter stage.
#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/depth/config_yaml.hpp>
#include <polyloc/eval/depth_quality.hpp>
#include <polyloc/sim/simulator.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

namespace polyloc::cli {
namespace cmd_eval_depth_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct EvalDepthArgs {
  std::string scenario, config, sensor;
  double duration = 0;
  bool full_rig = false, json = false;
};

nlohmann::json counts(const DepthQualityCounts& c) {
  return {{"outlier_removed", c.outlierRemoved()}, {"valid_kept", c.validKept()},
          {"flying_removed", c.flyingRemoved()},   {"reflection_removed", c.reflectionRemoved()},
          {"outliers", c.outliers},                {"valid", c.valid}};
}

void runEvalDepth(const EvalDepthArgs& a) {
  const Scenario s = loadScenario(a.scenario);
  const DepthFilterConfig cfg = a.config.empty() ? s.config.depth_filter : loadDepthFilterConfig(a.config);
  DepthQualityOptions o;
  o.sensor = a.sensor;
  o.duration = a.duration;
  o.camera_only = !a.full_rig;
  const DepthQualityResult r = evaluateDepthFilter(s, loadScenarioMap(s), cfg, o);
  const double fps = r.filter_s > 0 ? double(r.frames) / r.filter_s : 0.0;
  const DepthQualityCounts& c = r.combined;
  if (a.json) {
    nlohmann::json per = nlohmann::json::object(), rejected = nlohmann::json::object();
    for (const DepthFilterQuality& f : r.per_filter) {
      per[f.name] = counts(f.counts);
      per[f.name]["rejected_in_combined"] = f.rejected;
    }
    for (size_t k = 1; k < kDepthRejectKinds; ++k) rejected[depthRejectName(DepthReject(k))] = r.rejected[k];
    nlohmann::json j = {{"scenario", a.scenario}, {"sensor", r.sensor}, {"frames", r.frames}, {"pixels", r.pixels},
                        {"depth_outlier_removed", c.outlierRemoved()}, {"depth_valid_kept", c.validKept()},
                        {"combined", counts(c)}, {"per_filter", per}, {"rejected", rejected},
                        {"frames_per_s", fps}};
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("{}: {} frames of {} ({} pixels): {} outlier pixels ({} flying, {} reflection), {} valid\n",
             a.scenario, r.frames, r.sensor, r.pixels, c.outliers, c.flying, c.reflection, c.valid);
  fmt::print("{:<12} {:>16} {:>11} {:>8} {:>11}\n", "filter", "outliers removed", "valid kept", "flying", "reflection");
  auto row = [](const std::string& name, const DepthQualityCounts& q) {
    fmt::print("{:<12} {:>15.2f}% {:>10.2f}% {:>7.2f}% {:>10.2f}%\n", name, 100 * q.outlierRemoved(),
               100 * q.validKept(), 100 * q.flyingRemoved(), 100 * q.reflectionRemoved());
  };
  for (const DepthFilterQuality& f : r.per_filter) row(f.name, f.counts);
  row("combined", c);
  fmt::print("filter: {:.0f} frames/s (this machine's threads, batches of one simulated second)\n", fps);
}

}  // namespace cmd_eval_depth_impl

void registerEvalDepth(CLI::App& eval) {
  using namespace cmd_eval_depth_impl;
  auto a = std::make_shared<EvalDepthArgs>();
  CLI::App& c = *eval.add_subcommand("depth", "Depth filter vs the simulator's tagged ToF artefacts");
  c.add_option("--scenario", a->scenario, "Scenario YAML with a depth camera in its rig")->required()->check(CLI::ExistingFile);
  c.add_option("--config", a->config, "polyloc config or YAML with a depth_filter: section (default: the scenario's config)")
      ->check(CLI::ExistingFile);
  c.add_option("--sensor", a->sensor, "Depth camera of the rig (default: the first)");
  addDurationOption(c, a->duration, "Simulated seconds", "the scenario");
  c.add_flag("--full-rig", a->full_rig, "Simulate every sensor of the rig, not only the camera");
  c.add_flag("--json", a->json, "Result as one JSON object on stdout");
  c.callback([a] { runEvalDepth(*a); });
}

}  // namespace polyloc::cli
