// polyloc bench maps: the map representations side by side on one map. Per backend (factory.hpp):
// build time, memory, rays/s for planar scans and for 3D rays, point-in-solid queries/s, range
// error against Embree's exact intersection, and optionally MCL on a simulated scenario.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/bench_maps_localize.hpp"
#include "cli/bench_ranges.hpp"
#include "cli/bench_timing.hpp"
#include "cli/commands.hpp"

#include <polyloc/geometry/random.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/factory.hpp>
#include <polyloc/raycast/workload.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>


#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>

namespace polyloc::cli {
namespace cmd_bench_maps_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct BenchMapsArgs {
  std::string map, backends, markdown, localize;
  size_t rays = 100000;
  size_t beams = 100;
  double resolution = 0.05, height = 0.3, localize_duration = 30;
  int threads = 2, repeat = 3;
  uint64_t seed = 1;
  bool json = false, level_scanners = false;
};

struct Workload {
  std::vector<Pose> poses;  // planar scans
  BeamSet beams;
  std::vector<float> ox, oy, oz, dx, dy, dz;  // 3D rays
  std::vector<Eigen::Vector3f> points;       // point-in-solid queries
};

Workload makeWorkload(const Mesh& mesh, const BenchMapsArgs& a) {
  Workload w;
  const Eigen::AlignedBox3f b = mesh.bounds();
  w.beams = horizontalFan(a.beams, 30.f);
  w.poses = randomPlanarPoses(b, std::max<size_t>(1, a.rays / a.beams), a.height, a.seed);
  const CounterRng rng(a.seed);
  for (size_t i = 0; i < a.rays; ++i) {  // origins at sensor height, directions uniform on the sphere
    const Pose& p = w.poses[i % w.poses.size()];
    const double z = rng.uniform(-1, 1, 1, i, 0), phi = rng.uniform(-M_PI, M_PI, 1, i, 1);
    const double s = std::sqrt(1 - z * z);
    w.ox.push_back(float(p.x())), w.oy.push_back(float(p.y())), w.oz.push_back(float(p.z()));
    w.dx.push_back(float(s * std::cos(phi))), w.dy.push_back(float(s * std::sin(phi))), w.dz.push_back(float(z));
    w.points.emplace_back(float(rng.uniform(b.min().x(), b.max().x(), 2, i, 0)),
                          float(rng.uniform(b.min().y(), b.max().y(), 2, i, 1)),
                          float(rng.uniform(b.min().z(), b.max().z(), 2, i, 2)));
  }
  return w;
}

struct Results {
  std::vector<float> planar, rays3d;
  std::vector<uint8_t> inside;
};

// |r - ref| over rays where both hit: mean, median, p99; and the fraction whose hit/miss differs.
void rangeError(const std::vector<float>& r, const std::vector<float>& ref, nlohmann::json& j,
                const std::string& prefix) {
  const RangeStats s = rangeStats(r, ref);
  j[prefix + "mean_m"] = s.mean;
  j[prefix + "median_m"] = s.median;
  j[prefix + "p99_m"] = s.p99;
  j[prefix + "hit_disagreement"] = s.hit_disagreement;
}

nlohmann::json benchOne(const std::string& name, const Mesh& mesh, const Workload& w,
                        const BenchMapsArgs& a, Results& res) {
  CasterOptions co;
  co.threads = a.threads, co.resolution = a.resolution, co.height = a.height;
  std::unique_ptr<RayCaster> c;
  const double build_s = seconds([&] { c = makeCaster(name, mesh, co); });
  nlohmann::json j;
  j["build_s"] = build_s;
  j["memory_mb"] = double(c->memoryBytes()) / 1e6;
  j["threads"] = c->threads();
  res.planar.resize(w.poses.size() * w.beams.size());
  res.rays3d.resize(w.ox.size());
  res.inside.resize(w.points.size());
  const RayBatch rb{w.ox.data(), w.oy.data(), w.oz.data(), w.dx.data(), w.dy.data(), w.dz.data(),
                    nullptr, nullptr, w.ox.size()};
  j["rays_per_s_planar"] = bestRate(a.repeat, double(res.planar.size()),
                                    [&] { c->castScans(w.poses, w.beams, {res.planar.data()}); });
  j["rays_per_s_3d"] = bestRate(a.repeat, double(rb.count), [&] { c->castRays(rb, {res.rays3d.data()}); });
  j["point_queries_per_s"] = bestRate(a.repeat, double(w.points.size()),
                                      [&] { c->queryFree(w.points, 0.f, res.inside.data()); });
  return j;
}

std::string markdownTable(const nlohmann::json& j) {
  std::ostringstream s;
  s << "| backend | build s | memory MB | planar rays/s | 3D rays/s | point queries/s | range err mean m | median m | p99 m | 3D err mean m | median m | p99 m |\n"
    << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const auto& [name, b] : j["backends"].items())
    s << fmt::format("| {} | {:.3f} | {:.1f} | {:.3g} | {:.3g} | {:.3g} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} |\n", name,
                     b["build_s"].get<double>(), b["memory_mb"].get<double>(),
                     b["rays_per_s_planar"].get<double>(), b["rays_per_s_3d"].get<double>(),
                     b["point_queries_per_s"].get<double>(), b["range_err_mean_m"].get<double>(),
                     b["range_err_median_m"].get<double>(), b["range_err_p99_m"].get<double>(),
                     b["range_err_3d_mean_m"].get<double>(), b["range_err_3d_median_m"].get<double>(),
                     b["range_err_3d_p99_m"].get<double>());
  bool loc = false;
  for (const auto& [name, b] : j["backends"].items()) loc = loc || b.contains("localize");
  if (loc) {
    s << "\n| backend | sensors weighed | MCL updates/s | trans err mean m | trans err p95 m | yaw err mean deg | final status |\n"
      << "| --- | ---: | ---: | ---: | ---: | ---: | --- |\n";
    for (const auto& [name, b] : j["backends"].items()) {
      if (!b.contains("localize")) continue;
      const auto& l = b["localize"];
      if (l.contains("error")) {
        s << "| " << name << " | error: " << l["error"].get<std::string>() << " | | | | | |\n";
        continue;
      }
      s << fmt::format("| {} | {} | {:.1f} | {:.3f} | {:.3f} | {:.2f} | {} |\n", name, l["sensors"].size(),
                       l["updates_per_s"].get<double>(),
                       l["trans_err_mean_m"].get<double>(), l["trans_err_p95_m"].get<double>(),
                       l["yaw_err_mean_deg"].get<double>(), l["final_status"].get<std::string>());
    }
  }
  return s.str();
}

void runBenchMaps(const BenchMapsArgs& a) {
  checkOutputs({{"--map", a.map}}, {{"--markdown", a.markdown}});
  const Mesh mesh = loadMesh(a.map);
  const std::vector<std::string> names = a.backends.empty() ? casterNames() : splitList(a.backends);
  for (const std::string& n : names)  // fail before minutes of work, naming the bad one
    if (std::find(casterNames().begin(), casterNames().end(), n) == casterNames().end())
      makeCaster(n, mesh);  // throws: unknown name, lists the known ones
  const Workload w = makeWorkload(mesh, a);
  // The reference: Embree's exact intersection, always measured first.
  Results ref;
  nlohmann::json out, backends = nlohmann::json::object();
  fmt::print(stderr, "bench maps: {} ({} triangles), {} planar + {} 3D rays, {} points\n", a.map,
             mesh.numTriangles(), w.poses.size() * w.beams.size(), w.ox.size(), w.points.size());
  fmt::print(stderr, "  embree (reference) ...\n");
  nlohmann::json ej = benchOne("embree", mesh, w, a, ref);
  for (const std::string& n : names) {
    nlohmann::json j;
    Results r;
    if (n == "embree") {
      j = ej;
      r = ref;
    } else {
      fmt::print(stderr, "  {} ...\n", n);
      j = benchOne(n, mesh, w, a, r);
    }
    rangeError(r.planar, ref.planar, j, "range_err_");
    rangeError(r.rays3d, ref.rays3d, j, "range_err_3d_");
    size_t agree = 0;
    for (size_t i = 0; i < r.inside.size(); ++i) agree += r.inside[i] == ref.inside[i];
    j["point_agreement"] = r.inside.empty() ? 1.0 : double(agree) / double(r.inside.size());
    if (!a.localize.empty()) {
      fmt::print(stderr, "  {}: localising on {} ({} s) ...\n", n, a.localize, a.localize_duration);
      CasterOptions co;
      co.threads = a.threads, co.resolution = a.resolution, co.height = a.height;
      try {
        j["localize"] = benchLocalize(n, co, {a.localize, a.localize_duration, 0, a.level_scanners});
      } catch (const std::exception& e) {
        j["localize"] = {{"error", e.what()}};
      }
    }
    backends[n] = j;
  }
  out["map"] = a.map;
  out["triangles"] = mesh.numTriangles();
  out["resolution_m"] = a.resolution;
  out["height_m"] = a.height;
  out["rays"] = a.rays;
  out["backends"] = backends;
  if (!a.markdown.empty()) {
    std::ofstream md(a.markdown);
    md << markdownTable(out);
    if (!md) throw std::runtime_error("cannot write " + a.markdown);
  }
  if (a.json) fmt::print("{}\n", out.dump());
  else fmt::print("{}", markdownTable(out));
}

}  // namespace cmd_bench_maps_impl

void registerBenchMaps(CLI::App& bench) {
  using namespace cmd_bench_maps_impl;
  auto a = std::make_shared<BenchMapsArgs>();
  CLI::App& c = *bench.add_subcommand(
      "maps", "Map representations side by side (embree, grid2d, distance3d, octomap, ...): build "
              "time, memory, rays/s, point queries/s, range error against Embree, optional MCL run");
  addMapOption(c, a->map, "Map file (OBJ, PLY, STL, glTF, DAE)")->required();
  c.add_option("--backends", a->backends, "Comma-separated backends (default: all built)");
  c.add_option("--rays", a->rays, "Rays per workload (planar: rays / beams poses x beams)")->capture_default_str()->check(positiveFinite());
  c.add_option("--beams", a->beams, "Beams of the planar fan")->capture_default_str()->check(positiveFinite());
  c.add_option("--resolution", a->resolution, "Cell/voxel size of grid2d, distance3d, octomap (m)")->capture_default_str()->check(positiveFinite());
  addSensorHeightOption(c, a->height, "Sensor height of the planar rays and the grid2d slice (m)");
  addThreadsOption(c, a->threads, "Worker threads (0 = all cores)");
  c.add_option("--repeat", a->repeat, "Timed runs; the best is reported")->capture_default_str()->check(positiveFinite());
  addSeedOption(c, a->seed, "Seed of the random rays and points")->capture_default_str();
  c.add_option("--localize", a->localize, "Scenario YAML: also run MCL with each backend on it")->check(CLI::ExistingFile);
  c.add_flag("--level-scanners", a->level_scanners,
             "MCL of every backend weighs the rig's level planar scanners only (as grid2d always does)");
  c.add_option("--localize-duration", a->localize_duration, "Simulated seconds of the MCL run")->capture_default_str()->check(positiveFinite());
  c.add_option("--markdown", a->markdown, "Also write the table as Markdown to FILE");
  c.add_flag("--json", a->json, "Print one JSON object on stdout");
  c.callback([a] { runBenchMaps(*a); });
}

}  // namespace polyloc::cli
