#include "cli/bench_maps_localize.hpp"

#include <polyloc/eval/stats.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/sim/simulator.hpp>

#include <chrono>
#include <cmath>

namespace polyloc::cli {
nlohmann::json benchLocalize(const std::string& backend, const CasterOptions& options,
                             const BenchLocalizeArgs& a) {
  using Clock = std::chrono::steady_clock;
  Scenario scenario = loadScenario(a.scenario);
  if (a.duration > 0) scenario.duration = a.duration;
  Mesh map = loadScenarioMap(scenario);  // the static map, before the simulator moves chairs
  MclConfig cfg = scenario.config.mcl;
  if (a.particles > 0) cfg.particles = cfg.min_particles = cfg.max_particles = a.particles;
  cfg.threads = options.threads;
  cfg.caster = backend;
  cfg.caster_resolution = options.resolution;
  const Rig& rig = scenario.config.rig;
  if (backend == "grid2d" || a.level_scanners) {
    // A slice sees level scanners only and says nothing of z, roll and pitch: the refinement fits
    // x, y, yaw, as a 2D-grid localiser would (level_scanners: every backend on those terms).
    cfg.sensors.clear();
    for (size_t i = 0; i < rig.size(); ++i)
      if (rig.isLevelScanner(i)) cfg.sensors.push_back(rig.sensors[i].name);
    cfg.refine.dof = 3;
  }
  const EmbreeCaster exact(map);  // floor and free space, as in every polyloc localiser
  const std::unique_ptr<RayCaster> weigh = makeWeighingCaster(map, rig, cfg, options.threads);
  Simulator sim(scenario, map);
  Localizer loc(exact, map, rig, cfg, weigh.get());
  std::vector<std::string> weighed;
  const std::vector<uint8_t> on = weighedSensors(rig, cfg);
  for (size_t i = 0; i < rig.size(); ++i)
    if (on[i]) weighed.push_back(rig.sensors[i].name);

  bool started = false;
  double loc_s = 0;
  size_t updates = 0;
  std::vector<double> terr, yerr;
  SimHooks hooks;
  hooks.on_tick = [&](int64_t stamp, const Pose& gt, const Pose& odom) {
    const auto t0 = Clock::now();
    if (!started) {
      Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
      cov(0, 0) = cov(1, 1) = 0.1 * 0.1, cov(5, 5) = 0.05 * 0.05;
      cov(2, 2) = cov(3, 3) = cov(4, 4) = 1e-4;
      loc.initPose(gt, cov, stamp);
      started = true;
    }
    loc.addOdometry(stamp, odom);
    loc_s += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  hooks.on_frame = [&](const SimFrame& f) {
    if (!started) return;
    const auto t0 = Clock::now();
    const bool updated = loc.addScan(f.sensor, f.stamp_ns, f.measured);
    loc_s += std::chrono::duration<double>(Clock::now() - t0).count();
    if (!updated) return;
    ++updates;
    const MclEstimate e = loc.estimate();
    terr.push_back(std::hypot(e.pose.x() - f.map_T_base.x(), e.pose.y() - f.map_T_base.y()));
    yerr.push_back(std::abs(rad2deg(angleDiff(e.pose.yaw(), f.map_T_base.yaw()))));
  };
  NullRecordingWriter out;  // the bench needs the hooks, not a file
  const SimSummary s = sim.run(out, hooks);
  double tm = 0, ym = 0;
  for (double v : terr) tm += v;
  for (double v : yerr) ym += v;
  const double n = std::max<double>(1, double(terr.size()));
  return {{"scenario", a.scenario},
          {"sensors", weighed},
          {"slice_height_m", backend == "grid2d" ? nlohmann::json(weighingSliceHeight(rig, cfg)) : nlohmann::json()},
          {"sim_duration_s", s.sim_duration_s},
          {"particles", cfg.particles},
          {"updates", updates},
          {"localizer_s", loc_s},
          {"updates_per_s", loc_s > 0 ? double(updates) / loc_s : 0.0},
          {"trans_err_mean_m", tm / n},
          {"trans_err_p95_m", percentile(terr, 95)},
          {"yaw_err_mean_deg", ym / n},
          {"final_status", toString(loc.estimate().status)}};
}

}  // namespace polyloc::cli
