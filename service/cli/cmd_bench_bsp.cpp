// polyloc bench bsp: the solid-leaf BSP backend on a map (build time, size, rays/s for planar and
// 3D rays, point-in-solid queries/s) beside Embree on the same rays in the same run: the
// thesis's Table 6.1 measurement (100,000 random rays): the BSP and Embree rows, and the
// Bresenham rows (grid2d sliced at the ray height, at the thesis's 5, 4 and 1 cm) on the same
// planar rays and points.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/bench_ranges.hpp"
#include "cli/bench_timing.hpp"
#include "cli/commands.hpp"

#include <polyloc/geometry/random.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/bsp.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/factory.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

namespace polyloc::cli {
namespace cmd_bench_bsp_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct BenchBspArgs {
  std::string map;
  std::string labels;  // comma-separated: keep only these labels' solids
  std::vector<double> grid = {0.05, 0.04, 0.01};  // grid2d resolutions (m) of the Bresenham rows
  size_t rays = 100000;
  size_t points = 100000;
  int threads = 1;
  double height = 0.3;
  float clearance = 0.3f;
  float k = 0.8f;
  size_t max_candidates = 0;
  int repeat = 3;
  uint64_t seed = 1;
  bool json = false;
};

// Whole solids carry one label, so keeping labels keeps the map closed.
Mesh keepLabels(const Mesh& in, const std::string& list) {
  const std::vector<std::string> keep = splitList(list);
  Mesh out;
  out.source = in.source + " [" + list + "]";
  std::vector<uint32_t> remap(in.numVertices(), UINT32_MAX);  // shared vertices stay shared
  for (size_t t = 0; t < in.numTriangles(); ++t) {
    if (std::find(keep.begin(), keep.end(), in.labelOf(t)) == keep.end()) continue;
    Triangle tri = in.triangles[t];
    for (uint32_t& v : tri) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<uint32_t>(out.vertices.size());
        out.vertices.push_back(in.vertices[v]);
      }
      v = remap[v];
    }
    out.triangles.push_back(tri);
    out.triangle_label.push_back(out.labelId(in.labelOf(t)));
  }
  if (out.triangles.empty()) throw std::runtime_error("no triangle of " + in.source + " has a label in " + list);
  return out;
}

struct Rays {
  std::vector<float> ox, oy, oz, dx, dy, dz;
  RayBatch batch() const {
    return {ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, ox.size()};
  }
};

// n rays from free origins at height h (uniform in the map's x/y box, at least 1 cm from every
// surface, so that no origin lies on a floor: the lab's platform top is at 0.3 m, and who hits a
// surface the ray starts on is a tie), planar with uniform yaw or 3D, uniform on the sphere.
Rays randomRays(const Mesh& mesh, const BspCaster& bsp, size_t n, double h, bool planar, uint64_t seed) {
  const CounterRng rng(seed);
  const Eigen::AlignedBox3f box = mesh.bounds();
  Rays r;
  for (uint64_t i = 0; r.ox.size() < n && i < 100 * n; ++i) {
    const Eigen::Vector3f o(rng.uniform(box.min().x(), box.max().x(), 0, i, 0),
                            rng.uniform(box.min().y(), box.max().y(), 0, i, 1), float(h));
    uint8_t free = 0;
    bsp.queryFree({&o, 1}, 0.01f, &free);
    if (!free) continue;
    Eigen::Vector3f d;
    if (planar) {
      const double a = rng.uniform(-M_PI, M_PI, 1, i, 0);
      d = Eigen::Vector3f(float(std::cos(a)), float(std::sin(a)), 0.f);
    } else {
      d = Eigen::Vector3f(rng.normal(2, i, 0), rng.normal(2, i, 1), rng.normal(2, i, 2)).normalized();
    }
    r.ox.push_back(o.x()), r.oy.push_back(o.y()), r.oz.push_back(o.z());
    r.dx.push_back(d.x()), r.dy.push_back(d.y()), r.dz.push_back(d.z());
  }
  if (r.ox.empty()) throw std::runtime_error("no free point at height " + std::to_string(h) + " in " + mesh.source);
  return r;
}

void compareRanges(const std::vector<float>& r, const std::vector<float>& ref, nlohmann::json& j, const std::string& key) {
  const RangeStats s = rangeStats(r, ref);
  j["range_err_mean_m_" + key] = s.mean;
  j["range_err_median_m_" + key] = s.median;
  j["range_err_p99_m_" + key] = s.p99;
  j["agree_1mm_" + key] = s.agree_1mm;
  j["rays_" + key] = r.size();
}

// Rays/s of both casters on the same rays, interleaved (the machine is shared), how often their
// ranges agree within 1 mm (both misses agree), and the range error against Embree's exact
// intersection where both hit.
void compareRays(const RayCaster& bsp, const RayCaster& embree, const Rays& rays, int repeat,
                 nlohmann::json& jb, nlohmann::json& je, const std::string& key) {
  const size_t n = rays.ox.size();
  std::vector<float> rb(n), re(n);
  const RayBatch batch = rays.batch();
  double best_b = 0, best_e = 0;
  for (int i = 0; i < repeat; ++i) {
    best_b = std::max(best_b, bestRate(1, double(n), [&] { bsp.castRays(batch, {rb.data()}); }));
    best_e = std::max(best_e, bestRate(1, double(n), [&] { embree.castRays(batch, {re.data()}); }));
  }
  compareRanges(rb, re, jb, key);
  jb["rays_per_s_" + key] = best_b;
  je["rays_per_s_" + key] = best_e;
}

// The thesis's Bresenham rows: a grid sliced at the rays' height per resolution, on the same
// planar rays (ranges against Embree's) and points (2D: a point counts as the slice's cell).
nlohmann::json gridRows(const Mesh& mesh, const EmbreeCaster& embree, const Rays& planar,
                        const std::vector<Eigen::Vector3f>& pts, const std::vector<uint8_t>& free_ref,
                        const BenchBspArgs& a) {
  nlohmann::json rows = nlohmann::json::object();
  std::vector<float> ref(planar.ox.size()), r(planar.ox.size());
  embree.castRays(planar.batch(), {ref.data()});
  for (double res : a.grid) {
    if (!(res > 0)) continue;  // --grid 0: no Bresenham rows
    CasterOptions o;
    o.threads = a.threads, o.resolution = res, o.height = a.height;
    std::unique_ptr<RayCaster> grid;
    nlohmann::json g;
    g["build_s"] = seconds([&] { grid = makeCaster("grid2d", mesh, o); });
    g["memory_mb"] = double(grid->memoryBytes()) / 1e6;
    g["rays_per_s_planar"] = bestRate(a.repeat, double(r.size()), [&] { grid->castRays(planar.batch(), {r.data()}); });
    compareRanges(r, ref, g, "planar");
    std::vector<uint8_t> f(pts.size());
    g["point_queries_per_s"] = bestRate(a.repeat, double(pts.size()), [&] { grid->queryFree(pts, 0.f, f.data()); });
    size_t same = 0;
    for (size_t i = 0; i < pts.size(); ++i) same += f[i] == free_ref[i];
    g["point_agree"] = pts.empty() ? 1.0 : double(same) / double(pts.size());
    rows[fmt::format("{:g}", res)] = g;
  }
  return rows;
}

void runBenchBsp(const BenchBspArgs& a) {
  Mesh mesh = loadMesh(a.map);
  if (!a.labels.empty()) mesh = keepLabels(mesh, a.labels);
  BspOptions bo;
  bo.k = a.k;
  bo.max_candidates = a.max_candidates;
  bo.threads = a.threads;
  const BspCaster bsp(mesh, bo);
  EmbreeOptions eo;
  eo.threads = a.threads;
  std::unique_ptr<EmbreeCaster> embree_owner;
  const double embree_build = seconds([&] { embree_owner = std::make_unique<EmbreeCaster>(mesh, eo); });
  const EmbreeCaster& embree = *embree_owner;

  const BspStats& s = bsp.stats();
  nlohmann::json j, jb, je;
  jb["build_s"] = s.build_s;
  jb["memory_mb"] = s.memoryMb();
  jb["nodes"] = s.nodes;
  jb["depth"] = s.depth;
  jb["boundary_polygons"] = s.boundary_polygons;
  jb["split_polygons"] = s.split_polygons;
  jb["empty_leaves"] = s.empty_leaves;
  jb["solid_leaves"] = s.solid_leaves;
  je["build_s"] = embree_build;
  const Rays planar = randomRays(mesh, bsp, a.rays, a.height, true, a.seed);
  compareRays(bsp, embree, planar, a.repeat, jb, je, "planar");
  compareRays(bsp, embree, randomRays(mesh, bsp, a.rays, a.height, false, a.seed), a.repeat, jb, je, "3d");

  const CounterRng rng(a.seed);
  const Eigen::AlignedBox3f box = mesh.bounds();
  std::vector<Eigen::Vector3f> pts(a.points);
  for (size_t i = 0; i < pts.size(); ++i)
    for (int k = 0; k < 3; ++k) pts[i][k] = float(rng.uniform(box.min()[k], box.max()[k], 3, i, k));
  std::vector<uint8_t> fb(pts.size()), fe(pts.size());
  const double np = double(pts.size());
  jb["point_queries_per_s"] = bestRate(a.repeat, np, [&] { bsp.queryFree(pts, 0.f, fb.data()); });
  je["point_queries_per_s"] = bestRate(a.repeat, np, [&] { embree.queryFree(pts, 0.f, fe.data()); });
  size_t same = 0;
  for (size_t i = 0; i < pts.size(); ++i) same += fb[i] == fe[i];
  jb["point_agree"] = double(same) / np;
  // Bresenham rows against the BSP's free test (the exact one: winding number, raycast.md).
  const nlohmann::json grid = gridRows(mesh, embree, planar, pts, fb, a);
  jb["point_queries_per_s_clearance"] = bestRate(a.repeat, np, [&] { bsp.queryFree(pts, a.clearance, fb.data()); });
  je["point_queries_per_s_clearance"] = bestRate(a.repeat, np, [&] { embree.queryFree(pts, a.clearance, fe.data()); });

  j["map"] = mesh.source;
  j["triangles"] = mesh.numTriangles();
  j["threads"] = a.threads;
  j["height_m"] = a.height;
  j["clearance_m"] = a.clearance;
  j["k"] = a.k;
  j["bsp"] = jb;
  j["embree"] = je;
  j["grid2d"] = grid;
  j["thesis_bsp_rays_per_s"] = 100000.0 / 1.3;  // Table 6.1: 2110 polygons, 2x2.0 GHz laptop
  j["thesis_point_queries_per_s"] = 3.3e6;
  if (a.json) {
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("map {} ({} triangles), {} threads\n", mesh.source, mesh.numTriangles(), a.threads);
  fmt::print("bsp:    build {:.3f} s, {:.2f} MB, {} nodes, depth {}\n", s.build_s, s.memoryMb(), s.nodes, s.depth);
  fmt::print("embree: build {:.3f} s\n", embree_build);
  for (const char* k : {"rays_per_s_planar", "rays_per_s_3d", "point_queries_per_s", "point_queries_per_s_clearance"})
    fmt::print("  {:30s} bsp {:12.0f}  embree {:12.0f}\n", k, jb[k].get<double>(), je[k].get<double>());
  fmt::print("  ranges within 1 mm of embree: planar {:.4f}, 3d {:.4f}\n", jb["agree_1mm_planar"].get<double>(),
             jb["agree_1mm_3d"].get<double>());
  for (const auto& [res, g] : grid.items())
    fmt::print("grid2d {} m (Bresenham): build {:.3f} s, {:.2f} MB, {:.0f} planar rays/s, {:.0f} points/s, "
               "range err median {:.4f} m\n", res, g["build_s"].get<double>(), g["memory_mb"].get<double>(),
               g["rays_per_s_planar"].get<double>(), g["point_queries_per_s"].get<double>(),
               g["range_err_median_m_planar"].get<double>());
}

}  // namespace cmd_bench_bsp_impl

void registerBenchBsp(CLI::App& bench) {
  using namespace cmd_bench_bsp_impl;
  auto a = std::make_shared<BenchBspArgs>();
  CLI::App& c = *bench.add_subcommand(
      "bsp", "Solid-leaf BSP vs Embree on one map: build, memory, rays/s (planar at height H and 3D, "
             "from random free points), point-in-solid queries/s");
  addMapOption(c, a->map, "Map file (closed, outward-facing solids)")->required();
  c.add_option("--labels", a->labels, "Keep only the solids with these labels (comma-separated)");
  c.add_option("--rays", a->rays, "Random rays of each kind")->capture_default_str()->check(positiveFinite());
  c.add_option("--points", a->points, "Random points for the point-in-solid test")->capture_default_str()->check(positiveFinite());
  addThreadsOption(c, a->threads, "Worker threads (0 = all cores; 1 compares with the thesis)");
  addSensorHeightOption(c, a->height, "Height of the ray origins (m)");
  c.add_option("--robot-radius", a->clearance, "Robot radius of the second point test (m)")->capture_default_str()->check(finiteRange(0.0, 100.0));
  c.add_option("--k", a->k, "BSP score weight k of k * splits + (1 - k) * imbalance")->capture_default_str()->check(finiteRange(0.f, 1.f));
  c.add_option("--max-candidates", a->max_candidates, "BSP planes scored per node (0 = all)")->capture_default_str();
  c.add_option("--repeat", a->repeat, "Timed runs; the best is reported")->capture_default_str()->check(positiveFinite());
  c.add_option("--grid-resolutions", a->grid, "grid2d resolutions (m) of the Bresenham rows (0: none)")
      ->capture_default_str()->delimiter(',');
  addSeedOption(c, a->seed, "Seed of the random rays and points")->capture_default_str();
  c.add_flag("--json", a->json, "Print one JSON object on stdout");
  c.callback([a] { runBenchBsp(*a); });
}

}  // namespace polyloc::cli
