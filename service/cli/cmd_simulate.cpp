// polyloc simulate: runs a scenario (kernels/sim) and records it as MCAP (*.mcap) or as a ROS 2
// bag directory (anything else); optionally a TUM ground-truth file and a PNG of the run.
// Progress on stderr when it is a terminal; a summary (or --json) on stdout.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "viz/sim_plot.hpp"

#include <polyloc/io/recording.hpp>
#include <polyloc/io/tum.hpp>
#include <polyloc/sim/simulator.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace polyloc::cli {
namespace cmd_simulate_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct SimulateArgs {
  std::string scenario, out, ground_truth, plot;
  int64_t seed = -1;       // -1: the scenario's
  double duration = 0;     // 0: the scenario's
  double plot_time = -1;   // -1: the middle of the run
  bool json = false;
  bool no_output = false;  // hidden: simulate without writing (timing the simulator alone)
};

// Counts messages and the bytes of their payload arrays; writes nothing. For --no-output.
class NullWriter final : public RecordingWriter {
 public:
  void write(const std::string&, int64_t, const msg::Message& m) override {
    std::visit([&](const auto& v) { bytes += payload(v); }, m);
  }
  void close() override {}
  uint64_t bytes = 0;

 private:
  static uint64_t payload(const msg::LaserScan& s) { return 4 * (s.ranges.size() + s.intensities.size()) + 64; }
  static uint64_t payload(const msg::PointCloud2& p) { return p.data.size() + 128; }
  static uint64_t payload(const msg::Image& i) { return i.data.size() + 64; }
  template <class T>
  static uint64_t payload(const T&) { return 128; }
};

uint64_t pathBytes(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return fs::file_size(path, ec);
  uint64_t total = 0;
  if (fs::is_directory(path, ec))
    for (const auto& e : fs::recursive_directory_iterator(path, ec))
      if (e.is_regular_file(ec)) total += e.file_size(ec);
  return total;
}

void progressBar(double f, double sim_s) {
  fmt::print(stderr, "\rsimulate {} {:3.0f}% {:.1f} s", barText(f), 100 * f, f * sim_s);
  std::fflush(stderr);
}

void runSimulate(const SimulateArgs& a) {
  if (a.out.empty() && !a.no_output) throw std::runtime_error("--out is required");
  const bool mcap = a.out.size() > 5 && a.out.substr(a.out.size() - 5) == ".mcap";
  checkOutputs({{"--scenario", a.scenario}}, {{"--out", mcap ? a.out : ""}, {"--ground-truth", a.ground_truth}, {"--plot", a.plot}},
               {{"--out", mcap ? "" : a.out}});
  Scenario scenario = loadScenario(a.scenario);
  if (a.seed >= 0) scenario.seed = static_cast<uint64_t>(a.seed);
  if (a.duration > 0) scenario.duration = a.duration;
  Mesh map = loadScenarioMap(scenario);
  Simulator sim(scenario, std::move(map));

  std::unique_ptr<RecordingWriter> writer;
  NullWriter* null_writer = nullptr;
  if (a.no_output) {
    auto w = std::make_unique<NullWriter>();
    null_writer = w.get();
    writer = std::move(w);
  } else {
    if (auto dir = std::filesystem::path(a.out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    writer = a.out.ends_with(".mcap") ? createMcap(a.out) : createRos2Bag(a.out);
  }
  std::unique_ptr<TumWriter> tum;  // ground truth map -> base_link at the odometry rate
  if (!a.ground_truth.empty()) tum = std::make_unique<TumWriter>(a.ground_truth);

  // The plot: paths from every tick, one frame per sensor at plot_time.
  const double plot_time = a.plot_time >= 0 ? std::min(a.plot_time, sim.duration()) : 0.5 * sim.duration();
  viz::SimPlotData plot;
  plot.plot_time = plot_time;
  plot.people_paths.resize(sim.people().size());
  std::vector<bool> have_frame(scenario.config.rig.size(), false);
  plot.frames.resize(scenario.config.rig.size());
  bool have_robot = false;
  SimHooks hooks;
  hooks.on_tick = [&](int64_t stamp, const Pose& gt, const Pose&) {
    if (tum) tum->write({stamp, gt});
    if (a.plot.empty()) return;
    const double t = static_cast<double>(stamp - scenario.start_time_ns) * 1e-9;
    plot.truth_path.emplace_back(gt.x(), gt.y());
    for (size_t i = 0; i < sim.people().size(); ++i) {
      const PersonState p = sim.people().state(i, t, {gt.x(), gt.y()});
      if (p.present) plot.people_paths[i].emplace_back(p.x, p.y);
    }
    if (!have_robot && t >= plot_time) {
      have_robot = true;
      plot.robot = gt;
      for (const auto& q : scenario.config.robot.outline(0.05)) {
        const Eigen::Vector3d w = gt * Eigen::Vector3d(q.x(), q.y(), 0);
        plot.robot_outline.emplace_back(w.x(), w.y());
      }
      for (size_t i = 0; i < sim.people().size(); ++i) {
        const PersonState p = sim.people().state(i, t, {gt.x(), gt.y()});
        if (p.present) plot.people_now.emplace_back(p.x, p.y);
      }
    }
  };
  if (!a.plot.empty()) {
    hooks.on_frame = [&](const SimFrame& f) {
      if (have_frame[f.sensor] || f.t < plot_time) return;
      have_frame[f.sensor] = true;
      const Sensor& sensor = scenario.config.rig.sensors[f.sensor];
      const BeamSet beams = sensor.beams();
      auto& out = plot.frames[f.sensor];
      out.name = sensor.name;
      out.map_T_sensor = f.map_T_sensor;
      out.depth_camera = std::holds_alternative<DepthCameraSpec>(sensor.spec);
      for (size_t b = 0; b < f.measured.size(); ++b) {
        const float r = f.measured[b];
        if (!std::isfinite(r) || r >= beams.range_max) continue;
        const Eigen::Vector3d p = f.map_T_sensor * (double(r) * Eigen::Vector3d(beams.dx[b], beams.dy[b], beams.dz[b]));
        out.points.push_back(p.cast<float>());
      }
    };
  }
  const bool tty = !a.json && isatty(fileno(stderr));
  if (tty) hooks.on_progress = [&](double f) { progressBar(f, sim.duration()); };

  const auto t0 = std::chrono::steady_clock::now();
  const SimSummary summary = sim.run(*writer, hooks);
  writer->close();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (tty) fmt::print(stderr, "\n");
  tum.reset();
  const uint64_t bytes = null_writer ? null_writer->bytes : pathBytes(a.out);
  if (!a.plot.empty()) {
    plot.title = fmt::format("{} (seed {}), {:.0f} s", a.scenario, scenario.seed, sim.duration());
    if (auto dir = std::filesystem::path(a.plot).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    viz::drawSimulation(sim.world(), plot, a.plot);
  }

  const double rtf = wall > 0 ? summary.sim_duration_s / wall : 0.0;
  if (a.json) {
    nlohmann::json j;
    j["scenario"] = a.scenario;
    j["seed"] = scenario.seed;
    j["output"] = a.no_output ? "" : a.out;
    j["output_bytes"] = bytes;
    j["output_written"] = !a.no_output;
    j["sim_duration_s"] = summary.sim_duration_s;
    j["wall_s"] = wall;
    j["realtime_factor"] = rtf;
    j["messages"] = summary.messages;
    j["floor_misses"] = summary.floor_misses;
    j["chairs_moved"] = summary.chairs_moved;
    const WorldChanges& w = summary.world;
    j["world"] = {{"removed", w.removed}, {"added", w.added}, {"shifted", w.shifted}, {"clutter", w.clutter},
                  {"triangles", w.triangles_after}};
    nlohmann::json topics = nlohmann::json::object();
    for (const auto& [topic, count] : summary.topics) topics[topic] = count;
    j["topics"] = topics;
    if (!a.ground_truth.empty()) j["ground_truth"] = a.ground_truth;
    if (!a.plot.empty()) j["plot"] = a.plot;
    fmt::print("{}\n", j.dump());
    return;
  }
  fmt::print("scenario   {} (seed {})\n", a.scenario, scenario.seed);
  fmt::print("simulated  {:.1f} s in {:.2f} s wall: {:.1f}x real time\n", summary.sim_duration_s, wall, rtf);
  if (a.no_output) fmt::print("output     none (--no-output): {:.1f} MB of message payload\n", bytes / 1e6);
  else fmt::print("output     {}: {:.1f} MB\n", a.out, bytes / 1e6);
  fmt::print("messages   {}\n", summary.messages);
  for (const auto& [topic, count] : summary.topics)
    fmt::print("  {:<36} {:>7}  {:6.1f} Hz\n", topic, count,
               summary.sim_duration_s > 0 && count > 1 ? (count - 1) / summary.sim_duration_s : 0.0);
  if (summary.chairs_moved) fmt::print("chairs     {} moved\n", summary.chairs_moved);
  if (const WorldChanges& w = summary.world; w.triangles_after > 0)
    fmt::print("world      differs from the map: {} removed, {} added, {} solids shifted, {} clutter boxes, {} triangles\n",
               w.removed, w.added, w.shifted, w.clutter, w.triangles_after);
  if (summary.floor_misses) fmt::print("warning    {} floor probes found no floor (robot kept at z = 0 there)\n", summary.floor_misses);
  if (!a.ground_truth.empty()) fmt::print("truth      {}\n", a.ground_truth);
  if (!a.plot.empty()) fmt::print("plot       {}\n", a.plot);
}

}  // namespace cmd_simulate_impl

void registerSimulate(CLI::App& app) {
  using namespace cmd_simulate_impl;
  auto args = std::make_shared<SimulateArgs>();
  CLI::App& cmd = *app.add_subcommand(
      "simulate", "Simulate a scenario: sensors, odometry and ground truth as MCAP or a ROS 2 bag");
  cmd.add_option("--scenario", args->scenario, "Scenario YAML (maps/scenarios/*.yaml)")->required()->check(CLI::ExistingFile);
  cmd.add_option("--out", args->out, "Recording to write: *.mcap, otherwise a ROS 2 bag directory");
  addSeedOption(cmd, args->seed, "Random seed (default: the scenario's)");
  addDurationOption(cmd, args->duration, "Simulated seconds", "the scenario");
  cmd.add_option("--ground-truth", args->ground_truth, "Also write the ground truth as a TUM file");
  cmd.add_option("--plot", args->plot, "Draw the run as PNG: map, paths, one frame of every sensor");
  cmd.add_option("--plot-time", args->plot_time, "Time (s) of the sensor frames in the plot (default: middle)");
  cmd.add_flag("--json", args->json, "Print one JSON object (realtime_factor, sim_duration_s, wall_s, output_bytes, messages, topics)");
  cmd.add_flag("--no-output", args->no_output, "")->group("");  // hidden: time the simulator without a writer
  cmd.callback([args] { runSimulate(*args); });
}

}  // namespace polyloc::cli
