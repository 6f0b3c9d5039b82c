// Google Benchmark suite for the solid-leaf BSP backend on the same workload as bench_raycast
// (office map, 2000 random poses at 0.3 m x 100 beams), so its rows compare with Embree's:
//   build/bin/bench_bsp --benchmark_counters_tabular=true
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/bsp.hpp>
#include <polyloc/raycast/workload.hpp>

#include <benchmark/benchmark.h>

#include <memory>

namespace {

using namespace polyloc;

struct BspWorkload {
  Mesh mesh = loadMesh(POLYLOC_SOURCE_DIR "/maps/office.obj");
  BspCaster caster{mesh};
  std::vector<Pose> poses = randomPlanarPoses(mesh.bounds(), 2000, 0.3, 1);
  BeamSet beams = horizontalFan(100, 30.f);
  std::vector<float> range = std::vector<float>(poses.size() * beams.size());
};

BspWorkload& bspWorkload() {
  static BspWorkload w;
  return w;
}

void BM_BspScans(benchmark::State& state) {
  BspWorkload& w = bspWorkload();
  w.caster.setThreads(static_cast<int>(state.range(0)));
  const bool hit_info = state.range(1) != 0;
  const size_t n = w.range.size();
  std::vector<uint32_t> tri(n), label(n);
  std::vector<float> nx(n), ny(n), nz(n);
  const HitBuffers out = hit_info ? HitBuffers{w.range.data(), tri.data(), label.data(), nx.data(), ny.data(), nz.data()}
                                  : HitBuffers{w.range.data()};
  for (auto _ : state) w.caster.castScans(w.poses, w.beams, out);
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
// (threads, hit info): ranges only on 1 and 2 threads, then with triangle, label and normal.
BENCHMARK(BM_BspScans)->Args({1, 0})->Args({2, 0})->Args({1, 1})->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_BspFreeSpace(benchmark::State& state) {
  BspWorkload& w = bspWorkload();
  w.caster.setThreads(1);
  std::vector<Eigen::Vector3f> pts;
  for (const Pose& p : w.poses) pts.push_back(p.translation().cast<float>());
  std::vector<uint8_t> free(pts.size());
  for (auto _ : state) w.caster.queryFree(pts, static_cast<float>(state.range(0)) / 100.f, free.data());
  state.counters["queries_per_s"] =
      benchmark::Counter(static_cast<double>(pts.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BspFreeSpace)->Arg(0)->Arg(30)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_BspBuild(benchmark::State& state) {
  BspWorkload& w = bspWorkload();
  BspOptions opt;
  opt.max_candidates = static_cast<size_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(std::make_unique<BspCaster>(w.mesh, opt));
  state.counters["triangles"] = static_cast<double>(w.mesh.numTriangles());
}
// max_candidates: 0 (all planes, the default) and a sample of 64.
BENCHMARK(BM_BspBuild)->Arg(0)->Arg(64)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
