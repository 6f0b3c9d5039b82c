// polyloc demo: what `make run` shows for now. Loads (or generates) the bundled lab map, prints
// its validation summary, simulates a SICK S300 scan from a few free poses, prints the ranges
// and draws a top view of the map slice with the rays as PNG.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/output_check.hpp"
#include "cli/commands.hpp"
#include "viz/topview.hpp"

#include <polyloc/map/load.hpp>
#include <polyloc/map/validate.hpp>
#include <polyloc/mapgen/generate.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/workload.hpp>
#include <polyloc/sensors/sensor.hpp>

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <memory>

namespace polyloc::cli {
namespace cmd_demo_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct DemoArgs {
  std::string map = "maps/lab.obj";
  std::string out = "build/demo.png";
  int poses = 4;
  double height = 0.25;  // scanner height above the floor (m)
  uint64_t seed = 3;
};

// Candidate robot positions that are free of obstacles from the floor to head height and stand
// on a floor labelled "floor" (not outside the building, not on furniture).
std::vector<Pose> freePoses(const Mesh& mesh, const EmbreeCaster& caster, int count, uint64_t seed) {
  std::vector<Pose> out;
  const int64_t floor = mesh.findLabel("floor");
  const std::vector<Pose> cand = randomPlanarPoses(mesh.bounds(), 2000, 0.0, seed);
  for (const Pose& c : cand) {
    if (static_cast<int>(out.size()) == count) break;
    const float x = static_cast<float>(c.x()), y = static_cast<float>(c.y());
    const float down = -1.f, up = 0.f, z0 = 2.0f, t0 = 0.f, t1 = 3.f;
    float r;
    uint32_t label;
    caster.castRays({&x, &y, &z0, &up, &up, &down, &t0, &t1, 1}, {&r, nullptr, &label});
    if (!std::isfinite(r) || static_cast<int64_t>(label) != floor || std::abs(z0 - r) > 0.05f) continue;
    // Body points 0.55 m apart from 0.55 m up: 0.5 m clear of everything but the floor.
    const float zf = z0 - r;
    const std::vector<Eigen::Vector3f> body = {{x, y, zf + 0.55f}, {x, y, zf + 1.1f}, {x, y, zf + 1.65f}};
    uint8_t ok[3];
    caster.queryFree(body, 0.5f, ok);
    if (ok[0] && ok[1] && ok[2]) out.push_back(Pose::fromXYZRPY(x, y, zf, 0, 0, c.yaw()));
  }
  return out;
}

void runDemo(const DemoArgs& a) {
  checkOutputs({{"--map", a.map}}, {{"--out", a.out}});
  Mesh mesh;
  if (std::filesystem::exists(a.map)) {
    mesh = loadMesh(a.map);
  } else {
    fmt::print(stderr, "{} not found: generating the lab map in memory\n", a.map);
    mesh = generateMap("lab");
  }
  fmt::print("== map {}\n{}\n", a.map, validateMesh(mesh).summary());

  const EmbreeCaster caster(mesh);
  const Sensor scanner{"front", sickS300(), Pose::fromXYZRPY(0, 0, a.height, 0, 0, 0)};
  const BeamSet beams = scanner.beams();
  const std::vector<Pose> robots = freePoses(mesh, caster, a.poses, a.seed);
  if (robots.empty()) throw std::runtime_error("no free pose found on the floor of " + a.map);
  std::vector<Pose> sensors;
  for (const Pose& r : robots) sensors.push_back(scanner.worldPose(r));
  std::vector<float> range(sensors.size() * beams.size());
  std::vector<uint32_t> label(range.size());
  caster.castScans(sensors, beams, {range.data(), nullptr, label.data()});

  const auto box = mesh.bounds();
  viz::TopView view(Eigen::AlignedBox2f(box.min().head<2>(), box.max().head<2>()), 40.f);
  const viz::Color furniture = viz::kGray;
  view.drawMeshSlice(mesh, 0.74f, &furniture, 1);  // just under table tops, for orientation
  view.drawMeshSlice(mesh, static_cast<float>(a.height), nullptr, 2);
  const viz::Color colors[] = {viz::kRed, viz::kBlue, viz::kGreen, viz::kOrange};
  const size_t nb = beams.size();
  for (size_t p = 0; p < sensors.size(); ++p) {
    const Pose& s = sensors[p];
    size_t misses = 0;
    float rmin = INFINITY, rmax = 0;
    double sum = 0;
    for (size_t b = 0; b < nb; ++b) {
      const float r = range[p * nb + b];
      if (!std::isfinite(r)) {
        ++misses;
        continue;
      }
      rmin = std::min(rmin, r), rmax = std::max(rmax, r), sum += r;
      const Eigen::Vector3d e = s * (static_cast<double>(r) * Eigen::Vector3d(beams.dx[b], beams.dy[b], beams.dz[b]));
      if (b % 4 == 0) view.drawLine({s.x(), s.y()}, e.head<2>().cast<float>(), colors[p % 4], 1);
    }
    view.drawPose(robots[p], colors[p % 4], 0.3f);
    view.drawText(std::to_string(p + 1), {static_cast<float>(s.x()) + 0.35f, static_cast<float>(s.y())});
    fmt::print("== scan {} from x={:.2f} y={:.2f} z={:.2f} yaw={:.1f} deg ({} beams, S300 at {:.2f} m)\n",
               p + 1, robots[p].x(), robots[p].y(), robots[p].z(), rad2deg(robots[p].yaw()), nb, a.height);
    fmt::print("   min {:.3f} m  mean {:.3f} m  max {:.3f} m  misses {}\n", rmin,
               sum / std::max<size_t>(1, nb - misses), rmax, misses);
    fmt::print("   every 45 deg:");
    for (size_t b = 0; b < nb; b += 90)
      fmt::print("  {:+.0f}: {:.3f} ({})", rad2deg(sickS300().angleMin() + b * sickS300().resolution_rad),
                 range[p * nb + b], mesh.label_names[label[p * nb + b]]);
    fmt::print("\n");
  }
  view.drawLegend(fmt::format("{}: slice at {:.2f} m (black walls, cyan glass, red danger), "
                              "grey at 0.74 m; S300 rays from {} poses",
                              a.map, a.height, sensors.size()));
  view.drawScaleBar();
  if (auto dir = std::filesystem::path(a.out).parent_path(); !dir.empty())
    std::filesystem::create_directories(dir);
  view.save(a.out);
  fmt::print("== wrote {} ({}x{} px)\n", a.out, view.width(), view.height());
}

}  // namespace cmd_demo_impl

void registerDemo(CLI::App& app) {
  using namespace cmd_demo_impl;
  auto args = std::make_shared<DemoArgs>();
  CLI::App& demo = *app.add_subcommand(
      "demo", "Scan the bundled lab from a few poses: map summary, ranges, PNG top view with rays");
  demo.add_option("--map", args->map, "Map file (generated in memory if missing)")->capture_default_str();
  demo.add_option("--out", args->out, "PNG to write")->capture_default_str();
  demo.add_option("--poses", args->poses, "Number of robot poses")->capture_default_str()->check(finiteRange(1, 16));
  addSensorHeightOption(demo, args->height, "Scanner height (m)");
  addSeedOption(demo, args->seed, "Seed for picking free poses")->capture_default_str();
  demo.callback([args] { runDemo(*args); });
}

}  // namespace polyloc::cli
