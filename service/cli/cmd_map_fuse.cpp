// polyloc map fuse: a polygon map from depth frames with known poses (a TUM RGB-D or 7-Scenes
// folder, a bag with a depth camera and /ground_truth): TSDF fusion, marching cubes and quadric
// decimation in Open3D (kernels/fusion), validated, saved, with a picture.
#include "cli/commands.hpp"
#include "cli/output_check.hpp"
#include "cli/parse_number.hpp"
#include "cli/progress_bar.hpp"

#include <polyloc/fusion/recording_fusion.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>

#include "viz/fusion_plot.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <unistd.h>

namespace polyloc::cli {
namespace cmd_map_fuse_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct MapFuseArgs {
  std::string input, out, frames = "all", plot;
  FusionConfig fusion;
  size_t triangles = 300000;
  bool json = false;
};

void run(const MapFuseArgs& a) {
  checkOutputs({{"--input", a.input}}, {{"--out", a.out}, {"--plot", a.plot}});
  checkMeshPath(a.out);
  const FrameSelection selection = FrameSelection::parse(a.frames);
  FusionConfig cfg = a.fusion;
  cfg.max_triangles = a.triangles;
  cfg.validate();
  auto reader = openRecording(a.input);
  const bool tty = isatty(fileno(stderr));
  auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  const auto t0 = std::chrono::steady_clock::now();
  RecordingFusionStats st;
  Mesh mesh = fuseRecording(*reader, a.input, cfg, selection, st, [&](double f) {
    const auto now = std::chrono::steady_clock::now();
    if (!tty || (now - last < std::chrono::milliseconds(200) && f < 1.0)) return;
    last = now;
    fmt::print(stderr, "\r\033[Kmap fuse {} {:3.0f}%", barText(f, 30), 100 * f);
    std::fflush(stderr);
  });
  if (tty) fmt::print(stderr, "\r\033[K");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ReadStats& rs = reader->stats();
  for (size_t i = 0; i < std::min<size_t>(rs.warnings.size(), 5); ++i)
    fmt::print(stderr, "polyloc map fuse: warning: {}\n", rs.warnings[i]);
  if (rs.rejected > 5) fmt::print(stderr, "polyloc map fuse: {} bad records in all\n", rs.rejected);
  for (const std::string& w : st.warnings) fmt::print(stderr, "polyloc map fuse: skipped {}\n", w);
  if (mesh.triangles.empty())
    throw std::runtime_error(fmt::format("{}: nothing fused: {} depth frames on {}, {} selected by --frames {}, {} without "
                                         "a pose, {} bad", a.input, st.images, st.image_topic, st.selected, a.frames,
                                         st.without_pose, st.bad_images));
  mesh.source = a.input;
  const ValidationReport r = validateMesh(mesh);
  if (auto dir = std::filesystem::path(a.out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  saveMesh(mesh, a.out);
  const Eigen::AlignedBox3f& b = r.bounds;
  if (!a.plot.empty())
    viz::drawFusion(mesh, st.path,
                    fmt::format("polyloc map fuse {}: {} of {} frames ({}), voxel {:g} m, truncation {:g} m, depth {:g}..{:g} m\n"
                                "{} triangles (marching cubes {}), {} open edges; blue: camera path, green: start",
                                a.input, st.fused, st.images, a.frames, cfg.voxel, cfg.truncation, cfg.min_depth,
                                cfg.max_depth, r.triangles, st.fusion.triangles_marched, r.open_edges),
                    a.plot);
  nlohmann::json j{{"input", a.input},
                   {"out", a.out},
                   {"image_topic", st.image_topic},
                   {"camera", {{"width", st.camera.width}, {"height", st.camera.height}, {"fx", st.camera.fx()},
                               {"fy", st.camera.fy()}, {"cx", st.camera.cx() - 0.5}, {"cy", st.camera.cy() - 0.5}}},
                   {"rejected_records", rs.rejected},
                   {"frames", {{"images", st.images}, {"selected", st.selected}, {"fused", st.fused},
                               {"without_pose", st.without_pose}, {"bad", st.bad_images}, {"reasons", st.reasons}}},
                   {"fusion", {{"voxel_m", cfg.voxel}, {"truncation_m", cfg.truncation}, {"min_depth_m", cfg.min_depth},
                               {"max_depth_m", cfg.max_depth}, {"pixels_fused", st.fusion.pixels},
                               {"triangles_marched", st.fusion.triangles_marched}, {"max_triangles", cfg.max_triangles}}},
                   {"mesh", {{"triangles", r.triangles}, {"vertices", r.vertices}, {"open_edges", r.open_edges},
                             {"non_manifold_edges", r.non_manifold_edges}, {"degenerate_triangles", r.degenerate_triangles},
                             {"bounds_min", {b.min().x(), b.min().y(), b.min().z()}},
                             {"bounds_max", {b.max().x(), b.max().y(), b.max().z()}}}},
                   {"seconds", seconds},
                   {"frames_per_second", seconds > 0 ? double(st.fused) / seconds : 0.0}};
  if (!a.plot.empty()) j["plot"] = a.plot;
  if (a.json) {
    fmt::print("{}\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  fmt::print("{}: fused {} of {} depth frames on {} ({} without a pose, {} bad) in {:.1f} s\n", a.input, st.fused,
             st.images, st.image_topic, st.without_pose, st.bad_images, seconds);
  fmt::print("marching cubes {} triangles -> {} after decimation -> {}\n{}", st.fusion.triangles_marched, r.triangles,
             a.out, r.summary());
}

}  // namespace cmd_map_fuse_impl

void registerMapFuse(CLI::App& map) {
  using namespace cmd_map_fuse_impl;
  auto a = std::make_shared<MapFuseArgs>();
  CLI::App* c = map.add_subcommand(
      "fuse", "Build a polygon map from depth frames with known poses (TUM RGB-D or 7-Scenes folder, or a recording "
              "with a depth Image, its CameraInfo and /ground_truth): TSDF fusion, marching cubes, decimation");
  c->add_option("--input", a->input, "Recording or data set folder")->required()->check(CLI::ExistingPath);
  c->add_option("--out", a->out, "Output map (.ply, .obj, .stl, .gltf, .glb, .dae)")->required();
  c->add_option("--frames", a->frames, "Which depth frames, by index: all, even, odd, or FIRST:LAST[:STEP]")->capture_default_str();
  c->add_option("--voxel", a->fusion.voxel, "TSDF voxel (m)")->capture_default_str()->check(positiveFinite());
  c->add_option("--truncation", a->fusion.truncation, "Signed distance band either side of a surface (m)")
      ->capture_default_str()->check(positiveFinite());
  c->add_option("--min-depth", a->fusion.min_depth, "Nearer pixels are not fused (m)")->capture_default_str()->check(nonNegativeFinite());
  c->add_option("--max-depth", a->fusion.max_depth, "Farther pixels are not fused (m)")->capture_default_str()->check(positiveFinite());
  c->add_option("--triangles", a->triangles, "Decimate to this many triangles (0: keep all)")->capture_default_str();
  c->add_option("--plot", a->plot, "PNG: the mesh from two sides with the camera path");
  c->add_flag("--json", a->json, "Print one JSON object on stdout");
  c->callback([a] {
    try {
      run(*a);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("map fuse", e.what());
    }
  });
}

}  // namespace polyloc::cli
