// polyloc bench raycast: rays/s of the Embree batch caster on a map, against a plain loop of one
// rtcIntersect1 per ray over the same rays in the same run, and against one thread. With
// --caster NAME another backend (gpu, bsp, ...) against Embree in the same run: rays/s, build
// time, memory, and how many ranges agree with Embree's within 1 mm.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/bench_timing.hpp"
#include "cli/commands.hpp"

#include <polyloc/map/load.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/factory.hpp>
#include <polyloc/raycast/workload.hpp>
#ifdef POLYLOC_HAVE_GPU
#include <polyloc/raycast/gpu.hpp>
#endif

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <memory>

namespace polyloc::cli {
namespace cmd_bench_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct BenchRaycastArgs {
  std::string map;
  size_t poses = 20000;
  size_t beams = 100;
  int threads = 2;
  double height = 0.3;
  float range_max = 30.f;
  int repeat = 5;
  uint64_t seed = 1;
  std::string caster = "embree";
  bool json = false;
};

// A backend of makeCaster against Embree on the same rays, timed alternately.
void runBenchCaster(const BenchRaycastArgs& a) {
  const Mesh mesh = loadMesh(a.map);
  CasterOptions o;
  o.threads = a.threads;
  o.height = a.height;
  std::unique_ptr<RayCaster> caster;
  const double build_s = seconds([&] { caster = makeCaster(a.caster, mesh, o); });
  EmbreeOptions eo;
  eo.threads = a.threads;
  const EmbreeCaster embree(mesh, eo);
  const std::vector<Pose> poses = randomPlanarPoses(mesh.bounds(), a.poses, a.height, a.seed);
  const BeamSet beams = horizontalFan(a.beams, a.range_max);
  const size_t n = poses.size() * beams.size();
  std::vector<float> range(n), ref(n);
  const auto run = [&] { caster->castScans(poses, beams, {range.data()}); };
  const auto run_ref = [&] { embree.castScans(poses, beams, {ref.data()}); };
  run(), run_ref();  // warm-up: TBB workers, GPU buffers
  double best = 0, best_ref = 0;
  for (int i = 0; i < a.repeat; ++i) {
    best = std::max(best, bestRate(1, double(n), run));
    best_ref = std::max(best_ref, bestRate(1, double(n), run_ref));
  }
  size_t within = 0, disagree = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool h = std::isfinite(range[i]), hr = std::isfinite(ref[i]);
    disagree += h != hr;
    within += h == hr && (!h || std::abs(range[i] - ref[i]) <= 1e-3f);
  }
  nlohmann::json j;
  j["map"] = a.map;
  j["caster"] = a.caster;
  j["triangles"] = mesh.numTriangles();
  j["build_s"] = build_s;
  j["memory_bytes"] = caster->memoryBytes();
  j["poses"] = a.poses;
  j["beams"] = a.beams;
  j["threads"] = a.threads;
  j["rays"] = n;
  j["rays_per_s"] = best;
  j["embree_rays_per_s"] = best_ref;
  j["ratio_vs_embree"] = best / best_ref;
  j["within_1mm_of_embree"] = double(within) / double(n);
  j["hit_disagreement"] = double(disagree) / double(n);
#ifdef POLYLOC_HAVE_GPU
  if (const auto* g = dynamic_cast<const GpuCaster*>(caster.get())) {
    j["renderer"] = g->info().renderer;
    j["gl_version"] = g->info().version;
    j["software_renderer"] = g->info().software;
  }
#endif
  if (a.json) return fmt::print("{}\n", j.dump());
  fmt::print("map {} ({} triangles): {} built in {:.3f} s, {:.1f} MB\n", a.map, mesh.numTriangles(), a.caster, build_s,
             double(caster->memoryBytes()) / 1e6);
  if (j.contains("renderer")) fmt::print("  renderer: {} ({})\n", j["renderer"].get<std::string>(), j["gl_version"].get<std::string>());
  fmt::print("{} poses x {} beams at z = {} m\n", a.poses, a.beams, a.height);
  fmt::print("  {:<8}{:14.0f} rays/s\n  embree  {:14.0f} rays/s ({} threads; {} / embree = {:.3f})\n", a.caster, best,
             best_ref, a.threads, a.caster, best / best_ref);
  fmt::print("  ranges within 1 mm of Embree's: {:.3f} %, hit/miss disagreements {:.3f} %\n", 100.0 * double(within) / double(n),
             100.0 * double(disagree) / double(n));
}

void runBenchRaycast(const BenchRaycastArgs& a) {
  if (a.caster != "embree") return runBenchCaster(a);
  Mesh mesh = loadMesh(a.map);
  std::unique_ptr<EmbreeCaster> caster;
  const double build_s = seconds([&] { caster = std::make_unique<EmbreeCaster>(mesh); });
  const std::vector<Pose> poses = randomPlanarPoses(mesh.bounds(), a.poses, a.height, a.seed);
  const BeamSet beams = horizontalFan(a.beams, a.range_max);
  const size_t n = poses.size() * beams.size();
  const double rays = static_cast<double>(n);
  std::vector<float> range(n), single(n);

  caster->setThreads(a.threads);
  const auto packet = [&] { caster->castScans(poses, beams, {range.data()}); };
  const auto loop1 = [&] { caster->castScansSingle(poses, beams, single.data()); };
  packet();  // warm caches and TBB workers
  loop1();
  // Interleave the two so that load from other processes hits both alike.
  double packet_best = 0, single_best = 0;
  for (int i = 0; i < a.repeat; ++i) {
    packet_best = std::max(packet_best, bestRate(1, rays, packet));
    single_best = std::max(single_best, bestRate(1, rays, loop1));
  }
  double one_thread = packet_best;
  if (caster->threads() != 1) {
    caster->setThreads(1);
    one_thread = bestRate(std::max(1, a.repeat / 2), rays, packet);
    caster->setThreads(a.threads);
  }

  double sum = 0;
  size_t hits = 0, mismatches = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool hit = std::isfinite(range[i]);
    hits += hit;
    sum += hit ? range[i] : a.range_max;
    mismatches += std::abs((hit ? range[i] : a.range_max) -
                           (std::isfinite(single[i]) ? single[i] : a.range_max)) > 1e-4f;
  }
  nlohmann::json j;
  j["map"] = a.map;
  j["triangles"] = mesh.numTriangles();
  j["build_s"] = build_s;
  j["poses"] = a.poses;
  j["beams"] = a.beams;
  j["threads"] = caster->threads();
  j["height_m"] = a.height;
  j["rays"] = n;
  j["rays_per_s"] = packet_best;
  j["mean_range_m"] = sum / rays;
  j["hit_fraction"] = static_cast<double>(hits) / rays;
  j["rtcintersect1_rays_per_s"] = single_best;
  j["ratio_vs_rtcintersect1"] = packet_best / single_best;
  j["rays_per_s_1_thread"] = one_thread;
  j["speedup_vs_1_thread"] = packet_best / one_thread;
  j["range_mismatches_vs_rtcintersect1"] = mismatches;
  j["thesis_bsp_rays_per_s"] = 100000.0 / 1.3;  // 2110 polygons, 2x2.0 GHz laptop
  j["ratio_vs_thesis_bsp"] = packet_best / (100000.0 / 1.3);
  if (a.json) {
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("map {} ({} triangles, BVH build {:.3f} s)\n", a.map, mesh.numTriangles(), build_s);
  fmt::print("{} poses x {} beams at z = {} m, {} threads\n", a.poses, a.beams, a.height, caster->threads());
  fmt::print("  packets of 16:     {:12.0f} rays/s\n", packet_best);
  fmt::print("  rtcIntersect1 loop:{:12.0f} rays/s  (packets / loop = {:.3f})\n", single_best,
             packet_best / single_best);
  fmt::print("  1 thread:          {:12.0f} rays/s  (speed-up {:.2f}x)\n", one_thread,
             packet_best / one_thread);
  fmt::print("  mean range {:.3f} m, hits {:.1f} %\n", sum / rays, 100.0 * hits / rays);
}

}  // namespace cmd_bench_impl

void registerBench(CLI::App& app) {
  using namespace cmd_bench_impl;
  CLI::App& bench = *app.add_subcommand("bench", "Measure kernels (results as JSON with --json)");
  bench.require_subcommand(1);
  auto args = std::make_shared<BenchRaycastArgs>();
  CLI::App& rc = *bench.add_subcommand(
      "raycast", "Rays/s of the Embree caster: N random poses in the map's x/y box at height H, "
                 "B beams over 360 deg, misses counted as the range limit in the mean");
  addMapOption(rc, args->map, "Map file (OBJ, PLY, STL, glTF, DAE)")->required();
  rc.add_option("--poses", args->poses, "Number of poses N")->capture_default_str()->check(positiveFinite());
  rc.add_option("--beams", args->beams, "Beams per pose B")->capture_default_str()->check(positiveFinite());
  addThreadsOption(rc, args->threads, "Worker threads T (0 = all cores)");
  addSensorHeightOption(rc, args->height, "Sensor height H above z = 0 (m)");
  rc.add_option("--range-max", args->range_max, "Range limit (m)")->capture_default_str()->check(positiveFinite());
  rc.add_option("--repeat", args->repeat, "Timed runs; the best is reported")->capture_default_str()->check(positiveFinite());
  addSeedOption(rc, args->seed, "Seed of the random poses")->capture_default_str();
  rc.add_option("--caster", args->caster, "Backend to measure against Embree (raycast/factory: embree, gpu, bsp, ...)")
      ->capture_default_str()
      ->check(CLI::IsMember(casterNames()));
  rc.add_flag("--json", args->json, "Print one JSON object on stdout");
  rc.callback([args] { runBenchRaycast(*args); });
  registerBenchMcl(bench);
  registerBenchIpc(bench);
  registerBenchBsp(bench);
  registerBenchMaps(bench);
}

}  // namespace polyloc::cli
