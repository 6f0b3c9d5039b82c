// polyloc eval rgbd: a real depth sequence against a mesh of the same place
// (kernels/eval/rgbd_eval.hpp): the agreement floor (ICP from the ground truth) and the depth
// filter's precision and recall against labels from the mesh rendered at the ground truth.
#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/output_check.hpp"
#include "cli/progress_bar.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/eval/rgbd_eval.hpp>

#include "viz/rgbd_plot.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace polyloc::cli {
namespace cmd_eval_rgbd_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct EvalRgbdArgs {
  std::string input, map, frames, config, plot;
  size_t floor_every = 1;
  bool json = false;
};

void run(const EvalRgbdArgs& a) {
  checkOutputs({{"--input", a.input}, {"--map", a.map}, {"--config", a.config}}, {{"--plot", a.plot}});
  RgbdEvalOptions o;
  o.map = a.map;
  o.frames = a.frames;
  o.floor_every = a.floor_every;
  if (!a.config.empty()) o.filter = loadDepthFilterConfig(a.config);
  if (!a.frames.empty()) FrameSelection::parse(a.frames);  // a bad one before the work
  const bool tty = isatty(fileno(stderr));
  auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  if (tty)
    o.progress = [&](const std::string& stage, double f) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last < std::chrono::milliseconds(200) && f < 1.0) return;
      last = now;
      fmt::print(stderr, "\r\033[Keval rgbd {:<24} {} {:3.0f}%", stage, barText(f, 30), 100 * f);
      std::fflush(stderr);
    };
  const auto t0 = std::chrono::steady_clock::now();
  const RgbdEvalResult r = evaluateRgbd(a.input, o);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (tty) fmt::print(stderr, "\r\033[K");
  const double total = double(r.outliers + r.good);
  if (!a.plot.empty()) {
    const RgbdFilterStage& all = r.filter.back();
    viz::drawRgbdEval(r,
                      fmt::format("polyloc eval rgbd {}: {} frames against {} ({} triangles)\nfloor {:.2f} cm, {:.2f} deg "
                                  "RMSE; {:.2f}% outlier pixels; the filter removes {} at {:.1f}% precision, {:.1f}% recall",
                                  r.input, r.frames.size(), r.map, r.map_triangles, 100 * r.floor_rmse_translation,
                                  r.floor_rmse_rotation * 180 / M_PI, total > 0 ? 100 * double(r.outliers) / total : 0.0,
                                  all.removed, 100 * all.precision(), 100 * all.recall()),
                      a.plot);
  }
  if (a.json) {
    nlohmann::json filter = nlohmann::json::object();
    for (const RgbdFilterStage& s : r.filter)
      filter[s.name] = {{"removed", s.removed}, {"removed_outliers", s.removed_outliers}, {"removed_good", s.removed_good},
                        {"precision", s.precision()}, {"recall", s.recall()}};
    nlohmann::json j{{"input", r.input},
                     {"sample_frame", r.sample.index},
                     {"map", r.map},
                     {"map_triangles", r.map_triangles},
                     {"frames", r.frames.size()},
                     {"floor", {{"frames", r.floor_frames}, {"failed", r.floor_failed},
                                {"rmse_translation_cm", 100 * r.floor_rmse_translation},
                                {"rmse_rotation_deg", r.floor_rmse_rotation * 180 / M_PI}}},
                     {"labels", {{"outliers", r.outliers}, {"good", r.good}, {"ambiguous", r.ambiguous}, {"unlabelled", r.unlabelled},
                                 {"outlier_share", total > 0 ? double(r.outliers) / total : 0.0},
                                 {"tolerance_base_m", o.tolerance.base}, {"tolerance_per_m2", o.tolerance.per_m2},
                                 {"align_px", o.tolerance.align_px}}},
                     {"filter", filter},
                     {"filter_frames_per_s", r.filter_seconds > 0 ? double(r.frames.size()) / r.filter_seconds : 0.0},
                     {"seconds", seconds}};
    if (r.fused) j["fusion"] = {{"frames", r.fusion.fused}, {"triangles_marched", r.fusion.fusion.triangles_marched}};
    fmt::print("{}\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  fmt::print("{}: {} frames against {} ({} triangles)\n", r.input, r.frames.size(), r.map, r.map_triangles);
  fmt::print("agreement floor (ICP from the ground truth, {} frames, {} failed): {:.2f} cm, {:.2f} deg RMSE\n",
             r.floor_frames, r.floor_failed, 100 * r.floor_rmse_translation, r.floor_rmse_rotation * 180 / M_PI);
  fmt::print("labels: {} outlier and {} good pixels ({:.2f}% outliers; tolerance {:g} m + {:g} z^2), {} ambiguous "
             "(within {} px of an edge), {} unlabelled (no surface)\n",
             r.outliers, r.good, total > 0 ? 100 * double(r.outliers) / total : 0.0, o.tolerance.base,
             o.tolerance.per_m2, r.ambiguous, o.tolerance.align_px, r.unlabelled);
  fmt::print("{:<12} {:>10} {:>10} {:>8}\n", "stage", "removed", "precision", "recall");
  for (const RgbdFilterStage& s : r.filter)
    fmt::print("{:<12} {:>10} {:>9.1f}% {:>7.1f}%\n", s.name, s.removed, 100 * s.precision(), 100 * s.recall());
  fmt::print("{:.1f} s\n", seconds);
}

}  // namespace cmd_eval_rgbd_impl

void registerEvalRgbd(CLI::App& eval) {
  using namespace cmd_eval_rgbd_impl;
  auto a = std::make_shared<EvalRgbdArgs>();
  CLI::App* c = eval.add_subcommand(
      "rgbd", "A real depth sequence (TUM RGB-D, 7-Scenes, a bag with a depth camera and /ground_truth) against a "
              "mesh: the agreement floor and the depth filter's precision and recall");
  c->add_option("--input", a->input, "Data set folder or recording")->required()->check(CLI::ExistingPath);
  addMapOption(*c, a->map, "Mesh of the place (default: fused from the even frames, the odd ones evaluated)");
  c->add_option("--frames", a->frames, "Frames to evaluate: all, even, odd or FIRST:LAST[:STEP] (default: odd when "
                                       "fusing, else all)");
  c->add_option("--config", a->config, "polyloc config or a file with a depth_filter: section")->check(CLI::ExistingFile);
  c->add_option("--floor-every", a->floor_every, "Compute the floor on every n-th frame")->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  c->add_option("--plot", a->plot, "PNG: one frame's depth, the mesh rendered at its truth and the labels; the floor per frame");
  c->add_flag("--json", a->json, "Print one JSON object on stdout");
  c->callback([a] {
    try {
      run(*a);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("eval rgbd", e.what());
    }
  });
}

}  // namespace polyloc::cli
