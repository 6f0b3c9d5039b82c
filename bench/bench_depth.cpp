// Google Benchmark suite for the depth filter (kernels/depth): frames/s at the PMD O3D100's
// 64x50 and at 320x240, one frame at a time on one core and in batches over the TBB threads
// (the Arg). The frames are a floor and a wall with noise, a step edge with flying pixels and
// sprinkled outliers, so that every stage has work.
//   build/bin/bench_depth --benchmark_counters_tabular=true
#include <polyloc/depth/filter.hpp>
#include <polyloc/geometry/random.hpp>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <vector>

namespace {

using namespace polyloc;

DepthCameraSpec camera(int w, int h) {
  DepthCameraSpec c = pmdO3D100();
  c.width = w, c.height = h;
  return c;
}

// A synthetic frame k: floor (lower half), wall 3 m ahead, a box edge with mixed depths.
std::vector<float> frameDepth(const DepthCameraSpec& c, uint64_t k) {
  const CounterRng rng(k);
  std::vector<float> d(c.numBeams());
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      const size_t i = size_t(v) * c.width + u;
      const double y = (v + 0.5 - c.cy()) / c.fy();
      float z = y > 0.05 ? float(0.75 / y) : 3.f;  // floor below the horizon, wall above
      if (u > c.width / 3 && u < c.width / 2 && v < c.height * 2 / 3) z = 1.5f;  // a box
      if (u == c.width / 2 && rng.uniform(k, i, 8) < 0.5) z = 2.2f;              // flying pixels
      if (rng.uniform(k, i, 9) < 0.01) z *= 0.5f;                               // reflections
      d[i] = std::min(z, 7.f) + 0.005f * float(rng.normal(k, i, 0));
    }
  return d;
}

struct Frames {
  DepthCameraSpec cam;
  DepthFilter filter;
  std::vector<std::vector<float>> depth, amplitude;
  std::vector<DepthFrameView> views;
  std::vector<DepthFilterResult> results;
  Frames(int w, int h, size_t n)
      : cam(camera(w, h)), filter(cam, Pose::fromXYZRPY(0.3, 0, 0.75, 0, 0.17, 0)), depth(n), amplitude(n), results(n) {
    for (size_t k = 0; k < n; ++k) {
      depth[k] = frameDepth(cam, k);
      amplitude[k].resize(cam.numBeams());
      for (size_t i = 0; i < cam.numBeams(); ++i) amplitude[k][i] = 400.f / (depth[k][i] * depth[k][i]);
      views.push_back({w, h, depth[k].data(), amplitude[k].data(), nullptr});
    }
  }
};

Frames& frames(int w, int h) {
  static Frames small(64, 50, 64), large(320, 240, 32);
  return w == 64 ? small : large;
}

void setRate(benchmark::State& state, size_t frames_per_iteration) {
  state.counters["frames_per_s"] =
      benchmark::Counter(double(frames_per_iteration), benchmark::Counter::kIsIterationInvariantRate);
}

// One frame per call, the caller's thread.
void BM_DepthFilterFrame(benchmark::State& state) {
  Frames& f = frames(int(state.range(0)), int(state.range(1)));
  size_t k = 0;
  for (auto _ : state) {
    f.filter.apply(f.views[k], f.results[k]);
    k = (k + 1) % f.views.size();
  }
  setRate(state, 1);
}
BENCHMARK(BM_DepthFilterFrame)->Args({64, 50})->Args({320, 240})->UseRealTime();

// A batch of frames over `threads` TBB threads.
void BM_DepthFilterBatch(benchmark::State& state) {
  Frames& f = frames(int(state.range(0)), int(state.range(1)));
  tbb::task_arena arena(int(state.range(2)));
  for (auto _ : state) arena.execute([&] { f.filter.applyBatch(f.views, f.results); });
  setRate(state, f.views.size());
}
BENCHMARK(BM_DepthFilterBatch)->Args({64, 50, 1})->Args({64, 50, 2})->Args({320, 240, 1})->Args({320, 240, 2})->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
