// polyloc bench mcl: measurement updates per second of the localiser on a map (N particles x B
// beams of one planar scanner, all particles weighed, resampling included, refinement only with
// --refine), and the rays/s of the same rays cast directly through castScans in the same run,
// for the MCL / raycast ratio.
#include "cli/common_options.hpp"
#include "cli/parse_number.hpp"
#include "cli/commands.hpp"

#include <polyloc/map/load.hpp>
#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/sensor_model.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/raycast/factory.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <memory>

namespace polyloc::cli {
namespace cmd_bench_mcl_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

struct BenchMclArgs {
  std::string map;
  size_t particles = 10000;
  size_t beams = 100;
  int dof = 6;
  int threads = 2;
  int updates = 20;
  double height = 0.3;
  uint64_t seed = 1;
  std::string model = "beam";
  std::string caster = "embree";
  bool refine = false;
  bool json = false;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

void runBenchMcl(const BenchMclArgs& a) {
  const Mesh mesh = loadMesh(a.map);
  EmbreeCaster caster(mesh);
  caster.setThreads(a.threads);
  MclConfig cfg;
  cfg.dof = a.dof;
  cfg.particles = cfg.min_particles = cfg.max_particles = a.particles;
  cfg.kld = false;
  cfg.alpha_slow = cfg.alpha_fast = 0;
  cfg.beams_per_scan = a.beams;
  cfg.update_min_distance = 0;  // every scan is an update
  // The filter's update (weighing, resampling) as the thesis measured it, unless --refine: the
  // refinement after it (on by default since the real logs) is a stage of its own.
  cfg.refine.enabled = a.refine;
  cfg.threads = a.threads;
  cfg.seed = a.seed;
  cfg.model = a.model;
  cfg.caster = a.caster;

  PlanarScannerSpec spec;
  spec.fov_rad = deg2rad(270.0);
  spec.resolution_rad = spec.fov_rad / double(std::max<size_t>(a.beams, 2) - 1);
  spec.range_max = 30.0;
  Rig rig;
  rig.name = "bench";
  rig.add(Sensor{"scanner", spec, Pose::fromXYZRPY(0, 0, a.height, 0, 0, 0)}, "");
  const BeamSet beams = rig.sensors[0].beams();

  // A true pose on free floor; the robot turns on the spot so that no wall gets in its way.
  const std::vector<Pose> start = FreeFloor(caster, mesh, cfg).sampleFree(1, CounterRng(a.seed), 0);
  if (start.empty()) throw std::runtime_error("no free floor found in " + a.map);
  std::vector<Pose> truth;
  std::vector<std::vector<float>> scans;
  for (int i = 0; i <= a.updates; ++i) {
    truth.push_back(start[0] * Pose::planar(0, 0, 0.02 * i));
    const Pose sp = rig.sensors[0].worldPose(truth.back());
    scans.emplace_back(beams.size());
    caster.castScans(std::span<const Pose>(&sp, 1), beams, {scans.back().data()});
    for (float& r : scans.back())
      if (!std::isfinite(r)) r = float(spec.range_max);  // a max-range return
  }
  // The model's one-off set-up (the likelihood field builds its distance field here) is not timed.
  const double b0 = now();
  // mcl.caster: the particles are weighed against it; Embree keeps the floor and free space.
  const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(mesh, rig, cfg, a.threads);
  Localizer loc(caster, mesh, rig, cfg, weigh.get());
  const double setup_s = now() - b0;
  const RayCaster& weighing = weigh ? *weigh : caster;
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  cov(0, 0) = cov(1, 1) = 0.1 * 0.1, cov(5, 5) = 0.05 * 0.05;
  if (a.dof == 6) cov(2, 2) = 0.01 * 0.01, cov(3, 3) = cov(4, 4) = 0.01 * 0.01;
  loc.initPose(truth[0], cov, 0);
  loc.addOdometry(0, truth[0]);
  loc.addScan(0, 0, scans[0]);  // warm-up (TBB workers, buffers)
  size_t used = 0;
  for (float r : scans[0]) used += std::isfinite(r) && r >= beams.range_min && r < beams.range_max;
  used = std::min(used, a.beams);
  const double t0 = now();
  for (int i = 1; i <= a.updates; ++i) {
    const int64_t t = int64_t(i) * 100'000'000;
    loc.addOdometry(t, truth[i]);
    loc.addScan(0, t, scans[i]);
  }
  const double mcl_s = now() - t0;
  const double updates_per_s = a.updates / mcl_s;
  const double mcl_rays_per_s = updates_per_s * double(a.particles) * double(used);

  // The same particle poses and beams straight through castScans, unwindowed (as bench raycast).
  const ParticleSet& ps = loc.particles();
  std::vector<Pose> poses(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) poses[i] = rig.sensors[0].worldPose(ps.pose(i));
  std::vector<float> range(poses.size() * beams.size());
  weighing.castScans(poses, beams, {range.data()});
  double best = 0;
  for (int r = 0; r < 3; ++r) {
    const double s0 = now();
    weighing.castScans(poses, beams, {range.data()});
    best = std::max(best, double(range.size()) / (now() - s0));
  }
  const MclEstimate e = loc.estimate();
  nlohmann::json j;
  j["map"] = a.map;
  j["model"] = a.model;
  j["refine"] = a.refine;
  j["caster"] = weighing.name();
  j["model_setup_s"] = setup_s;
  j["particles"] = a.particles;
  j["beams"] = a.beams;
  j["beams_used"] = used;
  j["dof"] = a.dof;
  j["threads"] = caster.threads();
  j["updates"] = a.updates;
  j["updates_per_s"] = updates_per_s;
  j["rays_per_s"] = mcl_rays_per_s;
  j["raycast_rays_per_s"] = best;
  j["ratio_vs_raycast"] = mcl_rays_per_s / best;
  j["thesis_rays_per_s"] = 900.0 * 20 * 5;  // 900 particles x 20 beams x 5 Hz
  j["pos_err_m"] = std::hypot(e.pose.x() - truth.back().x(), e.pose.y() - truth.back().y());
  j["status"] = toString(e.status);
  if (a.json) return fmt::print("{}\n", j.dump());
  fmt::print("map {}: model {} on {}, {} particles x {} beams ({} used), dof {}, {} threads (model set-up {:.2f} s)\n",
             a.map, a.model, weighing.name(), a.particles, a.beams, used, a.dof, caster.threads(), setup_s);
  fmt::print("  MCL:       {:10.2f} updates/s  {:12.0f} rays/s\n", updates_per_s, mcl_rays_per_s);
  fmt::print("  castScans: {:12.0f} rays/s (same poses and beams, no windows); MCL / raycast = {:.3f}\n", best,
             mcl_rays_per_s / best);
}

}  // namespace cmd_bench_mcl_impl

void registerBenchMcl(CLI::App& bench) {
  using namespace cmd_bench_mcl_impl;
  auto args = std::make_shared<BenchMclArgs>();
  CLI::App& c = *bench.add_subcommand("mcl", "Measurement updates/s of the MCL localiser");
  addMapOption(c, args->map, "Map file (OBJ, PLY, STL, glTF, DAE)")->required();
  c.add_option("--particles", args->particles, "Particles N")->capture_default_str()->check(positiveFinite());
  c.add_option("--beams", args->beams, "Beams B of the planar scanner")->capture_default_str()->check(finiteRange(2, 100000));
  c.add_option("--dof", args->dof, "3 or 6")->capture_default_str()->check(CLI::IsMember({3, 6}));
  addThreadsOption(c, args->threads, "Worker threads T (0 = all cores)");
  c.add_option("--updates", args->updates, "Timed updates")->capture_default_str()->check(positiveFinite());
  addSensorHeightOption(c, args->height, "Scanner height above base (m)");
  addSeedOption(c, args->seed, "Seed")->capture_default_str();
  c.add_option("--model", args->model, "Measurement model (mcl.model)")->capture_default_str()->check(
      CLI::IsMember(sensorModelNames()));
  c.add_option("--caster", args->caster, "Map representation the particles are weighed against (mcl.caster)")
      ->capture_default_str()
      ->check(CLI::IsMember(casterNames()));
  c.add_flag("--refine", args->refine, "Refine the estimate after each update (mcl.refine, on in the configs); off: the filter alone");
  c.add_flag("--json", args->json, "Print one JSON object on stdout");
  c.callback([args] { runBenchMcl(*args); });
}

}  // namespace polyloc::cli
