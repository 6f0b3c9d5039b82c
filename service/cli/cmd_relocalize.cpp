// polyloc relocalize: many recordings (or time segments of long ones) through the localiser,
// side by side with TBB (--jobs) and across MPI ranks (mpirun -np K polyloc relocalize ...);
// rank 0 merges into DIR/<name>/{trajectory.tum,frames.csv,plot.png,summary.json} and
// DIR/summary.json (docs/relocalize.md). Exit 1 when any input did not run whole.
#include "cli/common_options.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "cli/parse_number.hpp"
#include "reloc/batch_merge.hpp"
#include "reloc/batch_plan.hpp"
#include "reloc/batch_run.hpp"
#include "reloc/cluster.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

namespace polyloc::cli {
namespace cmd_relocalize_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

using Clock = std::chrono::steady_clock;

struct RelocalizeArgs {
  reloc::BatchOptions batch;
  std::string map, config, sensors, covariance = "diag";
  bool json = false;
};

void runRelocalize(RelocalizeArgs& a) {
  const auto t_start = Clock::now();
  reloc::BatchOptions& o = a.batch;
  if (o.jobs < 1) throw std::runtime_error("--jobs: must be >= 1");
  std::vector<PathArg> ins{{"--map", a.map}, {"--config", a.config}};
  for (const auto& in : o.inputs) ins.push_back({"--input", in});
  checkOutputs(ins, {}, {{"--out", o.out_dir}});
  if (o.segment_s < 0 || o.warmup_s < 0) throw std::runtime_error("--segment and --warmup: must be >= 0");
  if (a.covariance == "full") o.covariance = reloc::CsvCovariance::Full;
  else if (a.covariance != "diag") throw std::runtime_error("--covariance: diag or full");
  const std::unique_ptr<reloc::Cluster> cluster = reloc::Cluster::join();
  const int rank = cluster->rank(), ranks = cluster->size();

  PolylocConfig cfg = loadConfig(a.config, {.map_optional = !a.map.empty(), .recorded_rig = true});
  cfg.mcl.threads = 0;  // weigh in the batch's arena (reloc/batch_run.hpp)
  if (cfg.rig_from_recording && (!a.sensors.empty() || cfg.mcl.caster != "embree"))
    throw std::runtime_error(fmt::format("{}: --sensors and mcl.caster {} need the rig's sensors in the config (rig: recorded "
                                         "takes them from each recording)", a.config, cfg.mcl.caster));
  o.base.sensors = reloc::sensorMask(cfg.rig, a.sensors);
  o.base.plot = true;
  const reloc::Plan plan = reloc::planBatch(o);
  const std::vector<size_t> mine = reloc::assignTasks(plan, rank, ranks);
  std::vector<std::string> labels;
  for (size_t t : mine) {
    const reloc::Task& task = plan.tasks[t];
    labels.push_back(task.segments > 1 ? fmt::format("{}#{}", plan.names[task.input], task.segment + 1) : plan.names[task.input]);
  }
  // One bar, on rank 0's terminal: the other ranks' lines would tear it apart.
  reloc::ProgressBoard progress(labels, rank == 0 && isatty(fileno(stderr)));

  // Nothing below may throw past the gather: every rank must reach it or rank 0 waits forever.
  std::optional<Mesh> mesh;
  std::vector<reloc::TaskOutcome> outcomes;
  try {
    mesh.emplace(loadMesh(a.map.empty() ? cfg.map.file : a.map, cfg.map.load));
    EmbreeOptions eo;
    eo.threads = -1;  // the caller's arena: the batch's
    EmbreeCaster caster(*mesh, eo);
    const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(*mesh, cfg.rig, cfg.mcl, -1);
    const int threads = o.threads > 0 ? o.threads : o.jobs;
    outcomes = reloc::runTasks({cfg, *mesh, caster, weigh.get()}, plan, mine, o.jobs, threads, rank, progress);
  } catch (const std::exception& e) {
    progress.message(fmt::format("polyloc relocalize: rank {} failed: {}", rank, e.what()));
    outcomes = reloc::failedTasks(mine, rank, fmt::format("rank {}: {}", rank, e.what()));
  }
  progress.close();
  for (const auto& oc : outcomes) {  // warnings of the job and of the reader (bad records)
    const std::string& input = plan.tasks[oc.task].job.input;
    for (const auto& line : oc.log)
      if (line.rfind("warning", 0) == 0) progress.message(fmt::format("polyloc relocalize: {}: {}", input, line));
    for (const auto& w : oc.result.warnings) progress.message(fmt::format("polyloc relocalize: warning: {}", w));
  }

  const std::vector<std::string> gathered = cluster->gather(reloc::encodeOutcomes(outcomes));
  if (rank != 0) return;
  std::vector<reloc::TaskOutcome> all;
  for (size_t r = 0; r < gathered.size(); ++r) {
    if (r == 0) continue;  // rank 0's own: at hand, not decoded
    for (auto& oc : reloc::decodeOutcomes(gathered[r])) all.push_back(std::move(oc));
  }
  for (auto& oc : outcomes) all.push_back(std::move(oc));
  if (!mesh) mesh.emplace(loadMesh(a.map.empty() ? cfg.map.file : a.map, cfg.map.load));  // for the plots
  const nlohmann::json context = {{"jobs", o.jobs}, {"threads", o.threads > 0 ? o.threads : o.jobs},
                                  {"ranks", ranks}, {"cluster", cluster->kind()}, {"map", a.map.empty() ? cfg.map.file : a.map},
                                  {"config", a.config}, {"tasks", plan.tasks.size()},
                                  {"wall_s", std::chrono::duration<double>(Clock::now() - t_start).count()}};
  const nlohmann::json summary = reloc::writeBatch(*mesh, o, plan, std::move(all), context);
  if (a.json) {
    fmt::print("{}\n", summary.dump());
  } else {
    for (const auto& in : summary["inputs"]) {
      std::string acc;
      if (in.contains("ate_rmse_m") && !in["ate_rmse_m"].is_null())
        acc = fmt::format(", ATE {:.3f} m, p95 {:.3f} m", in["ate_rmse_m"].get<double>(), in["p95_pos_err_m"].get<double>());
      const std::string status = in["status"];
      fmt::print("{:<8} {} ({}){}{}\n", status, in["input"].get<std::string>(), in["name"].get<std::string>(),
                 in.contains("frames") ? fmt::format(", {} frames", in["frames"].get<size_t>()) : std::string(), acc);
    }
    fmt::print("{} of {} inputs whole, {} ranks x {} jobs, {:.2f} s wall; outputs in {}\n",
               summary["succeeded"].get<size_t>(), o.inputs.size(), ranks, o.jobs, summary["wall_s"].get<double>(),
               o.out_dir);
  }
  if (!summary["all_succeeded"].get<bool>())
    throw std::runtime_error(fmt::format("relocalize: {} of {} inputs failed or are incomplete (see {}/summary.json)",
                                         summary["failed"].get<size_t>(), o.inputs.size(), o.out_dir));
}

}  // namespace cmd_relocalize_impl

void registerRelocalize(CLI::App& app) {
  using namespace cmd_relocalize_impl;
  auto args = std::make_shared<RelocalizeArgs>();
  reloc::BatchOptions& b = args->batch;
  CLI::App& cmd = *app.add_subcommand("relocalize", "Localise many recordings in batch (TBB jobs, MPI ranks under mpirun)");
  cmd.add_option("--input", b.inputs, "Recordings: MCAP, ROS 2 bag, CARMEN log, TUM RGB-D or 7-Scenes folder (one or more)")->required();
  cmd.add_option("--config", args->config, "polyloc config (maps/config/*.yaml): map, rig, mcl")->required();
  cmd.add_option("--out", b.out_dir, "Output folder: <name>/ per input and summary.json")->required();
  addMapOption(cmd, args->map, "Polygon map (default: the config's)");
  cmd.add_flag("--global", b.global, "Global localisation everywhere (default: the first ground-truth pose, if any)");
  cmd.add_option("--jobs", b.jobs, "Recordings (or segments) side by side in this process")->capture_default_str()->check(finiteRange(1, 4096));
  cmd.add_option("--threads", b.threads, "TBB threads of this process (default: --jobs)")->check(finiteRange(0, 4096));
  cmd.add_option("--segment", b.segment_s, "Split recordings into segments of this many seconds (0: whole)")->capture_default_str()->check(finiteRange(0.0, 1e7));
  cmd.add_option("--warmup", b.warmup_s, "Seconds the filter runs before each segment but the first")->capture_default_str()->check(finiteRange(0.0, 1e7));
  cmd.add_option("--covariance", args->covariance, "CSV covariance columns: diag or full")->capture_default_str();
  cmd.add_option("--restamp", b.base.restamp_hz, "Restamp every message by its order in the recording at this rate (Hz), for logs whose stamps do not increase")
      ->check(finiteRange(1e-3, 1e9));
  cmd.add_option("--sensors", args->sensors, "Rig sensors whose frames are used, comma-separated (default: all; the filter also weighs only the config's mcl.sensors)");
  cmd.add_flag("--json", args->json, "Print the summary (DIR/summary.json) as one JSON object");
  cmd.callback([args] { runRelocalize(*args); });
}

}  // namespace polyloc::cli
