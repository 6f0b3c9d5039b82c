// Google Benchmark of the virtual range scan with the lisa rig on the lab tour: one iteration is
// one VRS cycle, the frames of every sensor (2 x 541 S300 beams, 4 x 667 URG beams, 3200 ToF
// pixels) added and the scan updated, with the obstacle memory and the stairwell danger zone.
// Counters: p50 and p99 of the cycle in ms (the latency bound is 1 ms on 2 cores).
//   build/bin/bench_vrs --benchmark_counters_tabular=true
#include <polyloc/map/load.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/sim/simulator.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>

namespace {

using namespace polyloc;

struct Cycle {
  std::vector<SimFrame> frames;  // one of each rig sensor
};

struct Workload {
  Scenario scenario = loadScenario(POLYLOC_SOURCE_DIR "/maps/scenarios/lab_tour.yaml");
  Mesh map = loadScenarioMap(scenario);
  std::vector<Cycle> cycles;
  Workload() {
    scenario.duration = 30;
    Simulator sim(scenario, map);
    NullRecordingWriter sink;
    Cycle open;
    std::vector<bool> have(scenario.config.rig.size(), false);
    SimHooks hooks;
    hooks.on_frame = [&](const SimFrame& f) {
      if (have[f.sensor]) return;
      have[f.sensor] = true;
      open.frames.push_back(f);
      if (open.frames.size() == have.size()) {
        cycles.push_back(std::move(open));
        open = {};
        std::fill(have.begin(), have.end(), false);
      }
    };
    sim.run(sink, hooks);
  }
};

Workload& workload() {
  static Workload w;
  return w;
}

void BM_VrsCycleLisa(benchmark::State& state) {
  Workload& w = workload();
  VirtualRangeScanner vrs(w.scenario.config.rig, w.scenario.config.robot, w.scenario.config.vrs, &w.map);
  std::vector<double> ms;
  size_t k = 0;
  for (auto _ : state) {
    const Cycle& c = w.cycles[k++ % w.cycles.size()];
    const auto t0 = std::chrono::steady_clock::now();
    for (const SimFrame& f : c.frames) vrs.addFrame(f.sensor, f.stamp_ns, f.map_T_base, f.measured);
    const SimFrame& last = c.frames.back();
    benchmark::DoNotOptimize(vrs.update(last.stamp_ns, last.map_T_base));
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  state.counters["p50_ms"] = ms[ms.size() / 2];
  state.counters["p99_ms"] = ms[std::min(ms.size() - 1, ms.size() * 99 / 100)];
  state.counters["memory_cells"] = double(vrs.memory().size());
  state.counters["cycles"] = double(w.cycles.size());
}
BENCHMARK(BM_VrsCycleLisa)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
