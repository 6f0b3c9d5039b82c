// Google Benchmark suite for the ray casters on the bundled office map (about 10k triangles):
// Embree's packets of 16 vs one rtcIntersect1 per ray, windows, free-space queries; then the
// solid-leaf BSP backend on the same rays.
//   build/bin/bench_raycast --benchmark_counters_tabular=true
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/bsp.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/workload.hpp>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cmath>
#include <memory>

namespace {

using namespace polyloc;

struct Workload {
  Mesh mesh = loadMesh(POLYLOC_SOURCE_DIR "/maps/office.obj");
  EmbreeCaster caster{mesh};
  std::vector<Pose> poses = randomPlanarPoses(mesh.bounds(), 2000, 0.3, 1);
  BeamSet beams = horizontalFan(100, 30.f);
  std::vector<float> range = std::vector<float>(poses.size() * beams.size());
};

Workload& workload() {
  static Workload w;
  return w;
}

void setRate(benchmark::State& state, size_t rays) {
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ScansPacket16(benchmark::State& state) {
  Workload& w = workload();
  w.caster.setThreads(static_cast<int>(state.range(0)));
  for (auto _ : state) w.caster.castScans(w.poses, w.beams, {w.range.data()});
  setRate(state, w.range.size());
}
BENCHMARK(BM_ScansPacket16)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_ScansIntersect1(benchmark::State& state) {
  Workload& w = workload();
  w.caster.setThreads(static_cast<int>(state.range(0)));
  for (auto _ : state) w.caster.castScansSingle(w.poses, w.beams, w.range.data());
  setRate(state, w.range.size());
}
BENCHMARK(BM_ScansIntersect1)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// The floor the packets must beat: a plain loop straight on Embree, one thread, nothing but
// rtcIntersect1 and the hit distance (no windows, no facing, no tie rule: embree.cpp), on a
// scene built as EmbreeCaster builds its own.
void BM_LeanIntersect1Loop(benchmark::State& state) {
  Workload& w = workload();
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), w.mesh.vertices.size()));
  for (size_t i = 0; i < w.mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = w.mesh.vertices[i][k];
  auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(uint32_t), w.mesh.triangles.size()));
  for (size_t t = 0; t < w.mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) idx[3 * t + k] = w.mesh.triangles[t][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  for (auto _ : state) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    for (size_t p = 0; p < w.poses.size(); ++p) {
      const Eigen::Matrix3f R = w.poses[p].rotation().toRotationMatrix().cast<float>();
      const Eigen::Vector3f o = w.poses[p].translation().cast<float>();
      for (size_t b = 0; b < w.beams.size(); ++b) {
        const Eigen::Vector3f d = R * Eigen::Vector3f(w.beams.dx[b], w.beams.dy[b], w.beams.dz[b]);
        rh.ray = {o.x(), o.y(), o.z(), 0.f, d.x(), d.y(), d.z(), 0.f, w.beams.range_max, 0xFFFFFFFFu, 0, 0};
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        w.range[p * w.beams.size() + b] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
      }
    }
  }
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  setRate(state, w.range.size());
}
BENCHMARK(BM_LeanIntersect1Loop)->UseRealTime()->Unit(benchmark::kMillisecond);

// The beam model's use: each beam only looks +-0.5 m around an expected range.
void BM_ScansWindowed(benchmark::State& state) {
  Workload& w = workload();
  w.caster.setThreads(1);
  w.caster.castScans({w.poses.data(), 1}, w.beams, {w.range.data()});
  std::vector<float> t0(w.beams.size()), t1(w.beams.size());
  for (size_t b = 0; b < w.beams.size(); ++b) {
    const float r = std::isfinite(w.range[b]) ? w.range[b] : 30.f;
    t0[b] = std::max(0.f, r - 0.5f);
    t1[b] = r + 0.5f;
  }
  for (auto _ : state) w.caster.castScans(w.poses, w.beams, {w.range.data()}, {t0.data(), t1.data()});
  setRate(state, w.range.size());
}
BENCHMARK(BM_ScansWindowed)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_ScansWithHitInfo(benchmark::State& state) {
  Workload& w = workload();
  w.caster.setThreads(1);
  const size_t n = w.range.size();
  std::vector<uint32_t> tri(n), label(n);
  std::vector<float> nx(n), ny(n), nz(n);
  for (auto _ : state)
    w.caster.castScans(w.poses, w.beams, {w.range.data(), tri.data(), label.data(), nx.data(), ny.data(), nz.data()});
  setRate(state, n);
}
BENCHMARK(BM_ScansWithHitInfo)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_FreeSpace(benchmark::State& state) {
  Workload& w = workload();
  w.caster.setThreads(1);
  std::vector<Eigen::Vector3f> pts;
  for (const Pose& p : w.poses) pts.push_back(p.translation().cast<float>());
  std::vector<uint8_t> free(pts.size());
  for (auto _ : state) w.caster.queryFree(pts, static_cast<float>(state.range(0)) / 100.f, free.data());
  state.counters["queries_per_s"] =
      benchmark::Counter(static_cast<double>(pts.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_FreeSpace)->Arg(0)->Arg(30)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_BuildScene(benchmark::State& state) {
  Workload& w = workload();
  for (auto _ : state) benchmark::DoNotOptimize(std::make_unique<EmbreeCaster>(w.mesh));
  state.counters["triangles"] = static_cast<double>(w.mesh.numTriangles());
}
BENCHMARK(BM_BuildScene)->Unit(benchmark::kMillisecond);

// The BSP backend on the same poses and beams (its own caster, built on first use).
BspCaster& bspCaster() {
  static BspCaster c{workload().mesh};
  return c;
}

void BM_BspScans(benchmark::State& state) {
  Workload& w = workload();
  BspCaster& bsp = bspCaster();
  bsp.setThreads(static_cast<int>(state.range(0)));
  const bool hit_info = state.range(1) != 0;
  const size_t n = w.range.size();
  std::vector<uint32_t> tri(n), label(n);
  std::vector<float> nx(n), ny(n), nz(n);
  const HitBuffers out = hit_info ? HitBuffers{w.range.data(), tri.data(), label.data(), nx.data(), ny.data(), nz.data()}
                                  : HitBuffers{w.range.data()};
  for (auto _ : state) bsp.castScans(w.poses, w.beams, out);
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
// (threads, hit info): ranges only on 1 and 2 threads, then with triangle, label and normal.
BENCHMARK(BM_BspScans)->Args({1, 0})->Args({2, 0})->Args({1, 1})->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_BspFreeSpace(benchmark::State& state) {
  Workload& w = workload();
  BspCaster& bsp = bspCaster();
  bsp.setThreads(1);
  std::vector<Eigen::Vector3f> pts;
  for (const Pose& p : w.poses) pts.push_back(p.translation().cast<float>());
  std::vector<uint8_t> free(pts.size());
  for (auto _ : state) bsp.queryFree(pts, static_cast<float>(state.range(0)) / 100.f, free.data());
  state.counters["queries_per_s"] =
      benchmark::Counter(static_cast<double>(pts.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BspFreeSpace)->Arg(0)->Arg(30)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_BspBuild(benchmark::State& state) {
  Workload& w = workload();
  BspOptions opt;
  opt.max_candidates = static_cast<size_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(std::make_unique<BspCaster>(w.mesh, opt));
  state.counters["triangles"] = static_cast<double>(w.mesh.numTriangles());
}
// max_candidates: 0 (all planes, the default) and a sample of 64.
BENCHMARK(BM_BspBuild)->Arg(0)->Arg(64)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
