// polyloc eval nav: navigation missions in a closed loop, as a robot runs them: polylocd (started
// here, source clock) localises and builds the VRS from the simulated sensors, polynav (started
// here; it links only the C client) drives on it, and the simulated base executes its commands
// in lockstep (drive_loop.hpp), with people walking and chairs moved. Reports per mission and in
// all: reached, collisions (with what and where), smallest clearance, danger-zone entries, door
// passages and oscillations, goal error, time against the wavefront-optimal path. --vrs off runs
// the same missions with a VRS made of the level scanners only: what a 2D controller sees.
#include "engines/child_process.hpp"
#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "engines/drive_loop.hpp"
#include "engines/drive_report.hpp"
#include "engines/nav_missions.hpp"
#include "cli/output_check.hpp"
#include "cli/parse_number.hpp"
#include "viz/topview.hpp"

#include <polyloc/map/height_band.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/tracking/people_tracker.hpp>
#include <polynav/grid_io.hpp>
#include <polynav/hull.hpp>
#include <polynav/wavefront.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <sys/mman.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

namespace polyloc::cli {

using engines::ChildProcess;
using engines::DriveLoop;
using engines::DriveLoopOptions;
using engines::MissionTracker;
using engines::MissionResult;
using engines::executableDir;
using engines::driveJson;
namespace cmd_eval_nav_impl {  // named, not anonymous: the CLI is compiled in batches (unity build)

namespace fs = std::filesystem;

struct Args {
  std::string scenario, vrs = "on", local = "nd", plot, keep;
  size_t missions = 10;
  int threads = 2;
  int live_port = 0;  // the internal polylocd's live view: none unless asked
  int64_t seed = -1;
  double rate = 1000, margin = 60;
  bool json = false, quiet = false;
};

std::vector<polynav::GoalSpot> drawGoals(const NavigationSpec& nav, const polynav::Zones& z, size_t n, uint64_t seed) {
  std::vector<polynav::GoalSpot> out;
  if (!nav.goals.empty()) {
    for (size_t k = 0; k < n; ++k) {
      const std::string& name = nav.goals[k % nav.goals.size()];
      const auto i = z.goalIndex(name);
      if (!i) throw std::runtime_error(fmt::format("navigation.goals: no goal '{}' in {}", name, nav.zones));
      out.push_back(z.goals[*i]);
    }
    return out;
  }
  if (z.goals.size() < 2) throw std::runtime_error(fmt::format("{}: random missions need at least 2 goals", nav.zones));
  return polynav::randomGoals(z, n, seed);
}

// The scenario's config for this polylocd: absolute paths, the source clock (lockstep), no TCP
// control endpoint (parallel runs), and for --vrs off a VRS of the level scanners alone.
std::string writeDaemonConfig(const Scenario& s, const std::string& instance, bool vrs_on, int live_port,
                              const fs::path& dir) {
  const fs::path src = s.config.file;
  YAML::Node y = YAML::LoadFile(src.string());
  auto absolute = [&](const char* key) {
    if (y[key] && y[key].IsScalar()) y[key] = fs::absolute(src.parent_path() / y[key].as<std::string>()).string();
    else if (y[key] && y[key].IsMap() && y[key]["file"])
      y[key]["file"] = fs::absolute(src.parent_path() / y[key]["file"].as<std::string>()).string();
  };
  absolute("map");
  absolute("rig");
  y["polylocd"]["instance"] = instance;
  y["polylocd"]["clock"] = "source";
  y["polylocd"]["control"]["enabled"] = false;
  y["polylocd"]["live"]["port"] = live_port;  // 0 unless asked: the user's live port (8765) stays theirs
  if (vrs_on && !s.navigation.vrs_sources.empty()) {
    YAML::Node sources(YAML::NodeType::Sequence);
    for (const auto& [sensor, mode] : s.navigation.vrs_sources) {
      YAML::Node n;
      n["sensor"] = sensor;
      n["mode"] = mode;
      sources.push_back(n);
    }
    y["vrs"]["sources"] = sources;
  }
  if (!vrs_on) {
    PeopleTracker tracker(s.config.rig, s.config.tracking);
    YAML::Node sources(YAML::NodeType::Sequence);
    for (size_t k = 0; k < s.config.rig.size(); ++k) {
      const bool level = std::find(tracker.sensors().begin(), tracker.sensors().end(), k) != tracker.sensors().end();
      YAML::Node n;
      n["sensor"] = s.config.rig.sensors[k].name;
      n["mode"] = level ? "direct" : "off";
      sources.push_back(n);
    }
    y["vrs"]["sources"] = sources;
    y["vrs"]["danger_labels"] = YAML::Node(YAML::NodeType::Sequence);
    y["vrs"].remove("danger_zones");
  }
  const fs::path out = dir / "polylocd.yaml";
  std::ofstream(out) << y << "\n";
  return out.string();
}

void plotRun(const Mesh& map, const polynav::Zones& zones, const std::vector<Eigen::Vector2f>& path,
             const MissionTracker& t, const std::vector<polynav::GoalSpot>& goals, const std::string& title,
             const std::string& png) {
  Eigen::AlignedBox2f box;
  for (const auto& v : map.vertices) box.extend(v.head<2>());
  viz::TopView view(box, 40.f);
  view.drawMeshSlice(map, 0.1f);
  view.drawMeshSlice(map, 0.75f, &viz::kGray, 1);
  for (const auto& d : zones.danger)
    for (size_t i = 0; i < d.polygon.size(); ++i)
      view.drawLine(d.polygon[i].cast<float>(), d.polygon[(i + 1) % d.polygon.size()].cast<float>(), viz::kRed, 2);
  for (size_t i = 1; i < path.size(); ++i) view.drawLine(path[i - 1], path[i], viz::kBlue, 2);
  for (const auto& g : goals) view.drawPose(Pose::planar(g.pose.x(), g.pose.y(), g.pose.z()), viz::kGreen, 0.3f);
  size_t collisions = 0, reached = 0;
  for (const MissionResult& m : t.results()) {
    reached += m.reached;
    for (const CollisionEvent& c : m.collisions) {
      ++collisions;
      view.drawPoint(c.contact.where.head<2>().cast<float>(), viz::kRed, 7);
      view.drawText(c.contact.label, c.contact.where.head<2>().cast<float>() + Eigen::Vector2f(0.15f, 0.15f), viz::kRed);
    }
  }
  view.drawLegend(fmt::format("{}: {}/{} reached, {} collisions (red), path blue, goals green", title, reached,
                              t.results().size(), collisions));
  view.drawScaleBar();
  view.save(png);
}

void run(const Args& a) {
  checkOutputs({{"--scenario", a.scenario}}, {{"--plot", a.plot}});
  Scenario s = loadScenario(a.scenario);
  if (a.seed >= 0) s.seed = uint64_t(a.seed);
  if (s.navigation.zones.empty()) throw std::runtime_error(a.scenario + ": no navigation.zones (docs/navigation.md)");
  const polynav::Zones zones = polynav::loadZones(s.navigation.zones);
  const std::vector<polynav::GoalSpot> goals = drawGoals(s.navigation, zones, a.missions, s.seed);
  const Mesh map = loadScenarioMap(s);

  // Work files: the controller's grid, polylocd's config, the logs of both.
  const std::string instance = fmt::format("evalnav{}", getpid());
  const fs::path dir = a.keep.empty() ? fs::temp_directory_path() / instance : fs::path(a.keep);
  fs::create_directories(dir);
  HeightBandOptions hb;
  hb.height = s.config.robot.height;
  if (a.vrs == "off") {
    // What a 2D robot knows of the building: its map is what its level scanners see (table legs,
    // not table tops), so it plans where only the VRS would tell it the robot does not fit.
    PeopleTracker tracker(s.config.rig, s.config.tracking);
    double z = 0;
    for (size_t k : tracker.sensors()) z = std::max(z, s.config.rig.sensors[k].mount.z());
    hb.height = std::max(hb.clearance + 0.05, z + 0.1);
  }
  hb.clearance = s.config.vrs.floor_clearance;
  hb.danger_labels = s.config.vrs.danger_labels;
  const HeightBand band = heightBandGrid(map, hb);
  saveHeightBand(band, (dir / "nav.yaml").string());
  const std::string daemon_cfg = writeDaemonConfig(s, instance, a.vrs == "on", a.live_port, dir);

  // The wavefront-optimal length of each mission, on the controller's own grid.
  polynav::LoadedGrid grid = polynav::loadNavGrid((dir / "nav.yaml").string());
  for (size_t i = 0; i < grid.danger.size(); ++i) grid.grid.occupied[i] |= grid.danger[i];
  polynav::Polygon footprint;
  for (const auto& p : s.config.robot.footprint) footprint.emplace_back(p.x(), p.y());
  if (footprint.empty())  // a round robot: its bounding square
    for (const auto& [x, y] : {std::pair{1, 1}, std::pair{-1, 1}, std::pair{-1, -1}, std::pair{1, -1}})
      footprint.emplace_back(x * s.config.robot.radius, y * s.config.robot.radius);
  const polynav::RectHull hull = polynav::RectHull::fromFootprint(footprint);
  const polynav::NavGrid inflated = polynav::inflate(grid.grid, std::max(hull.left, hull.right) + 0.05);
  polynav::Wavefront wave;
  auto optimal = [&](const Eigen::Vector2d& from, const polynav::GoalSpot& g) {
    const polynav::WavefrontPlan p = wave.plan(inflated, {}, from, polynav::approachPose(g).head<2>());
    return p.reachable ? p.length_m + g.approach : std::numeric_limits<double>::quiet_NaN();
  };
  MissionTracker tracker(zones, goals, footprint, optimal);

  const std::string bin = executableDir();
  const Waypoint& start = s.route.waypoints.at(0);
  ChildProcess daemon({bin + "/polylocd", "--config", daemon_cfg, "--instance", instance, "--threads", std::to_string(a.threads), "--log-level", "warn",
                       "--init", fmt::format("{},{},{}", start.p.x(), start.p.y(), s.navigation.start_yaw * 180 / M_PI)},
                      (dir / "polylocd.out").string(), (dir / "polylocd.log").string());
  std::string names;
  for (const auto& g : goals) names += (names.empty() ? "" : ",") + g.name;
  std::vector<std::string> nav_argv{bin + "/polynav", "--shm", instance, "--grid", (dir / "nav.yaml").string(), "--zones",
                                    s.navigation.zones, "--goals", names, "--local", a.local, "--mission-timeout",
                                    fmt::format("{}", s.navigation.mission_timeout), "--exit-when-done", "--json", "--quiet"};
  std::string footprint_arg;
  for (const auto& p : footprint) footprint_arg += fmt::format("{}{},{}", footprint_arg.empty() ? "" : ";", p.x(), p.y());
  nav_argv.insert(nav_argv.end(), {"--footprint", footprint_arg});
  if (!a.keep.empty()) nav_argv.insert(nav_argv.end(), {"--trace", (dir / "polynav.csv").string()});
  ChildProcess nav(nav_argv, (dir / "polynav.json").string(), (dir / "polynav.log").string());

  Simulator sim(s, map);
  DriveLoopOptions o;
  o.rate = a.rate;
  // Both programs are ours and alive (checked every step): waits may be long on a loaded machine
  // without changing the run.
  o.wait_vrs_s = 30, o.wait_command_s = 30, o.wait_attach_s = 60;
  DriveLoop loop(sim, instance, o);
  loop.controller_alive = [&] { return nav.running(); };
  if (!loop.waitForController(60, [&] { return nav.running() && daemon.running(); }))
    throw std::runtime_error(fmt::format("polynav did not start listening on '{}' (its log: {})", instance,
                                         (dir / "polynav.log").string()));
  // Bodies grown by these margins measure the clearance (the smallest that touches bounds it).
  const std::vector<double> margins{0.01, 0.02, 0.03, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3};
  std::vector<BodyCollider> grown;
  for (double m : margins) {
    RobotSpec r = s.config.robot;
    r.radius += m;
    for (auto& p : r.footprint) p += Eigen::Vector2d(p.x() > 0 ? m : -m, p.y() > 0 ? m : -m);  // a rectangle grown
    grown.emplace_back(sim.world(), r, 0.02);
  }
  size_t collisions_seen = 0;
  loop.on_command = [&](const polyloc_command& c, double t) { tracker.onCommand(c.goal, c.nav_state, c.status, t, loop.drive().truth()); };
  const double limit = double(goals.size()) * s.navigation.mission_timeout + a.margin;
  std::vector<Eigen::Vector2f> path;
  double next_clearance = 0;
  const bool tty = isatty(fileno(stderr));
  auto last_print = std::chrono::steady_clock::now();
  while (!tracker.done()) {
    if (loop.nowS() > limit) {
      tracker.abort(loop.nowS(), "evaluation time limit");
      break;
    }
    if (!daemon.running()) {
      tracker.abort(loop.nowS(), "polylocd ended");
      break;
    }
    if (!nav.running()) {
      // polynav ends after its last goal (--exit-when-done), its stop written: the base brakes
      // and the last mission is scored where it comes to rest (or ends failed if it was open).
      if (!tracker.settling()) {
        tracker.abort(loop.nowS(), "polynav ended");
        break;
      }  // else the loop stops waiting for it (controller_alive)
    }
    loop.step();
    const DriveSim& d = loop.drive();
    const Pose truth = d.truth();
    while (collisions_seen < d.collisions().size()) tracker.onCollision(d.collisions()[collisions_seen++]);
    double clearance = std::numeric_limits<double>::infinity();
    if (d.nowS() >= next_clearance) {
      next_clearance = d.nowS() + 0.1;
      const PeopleScene people = sim.people().scene(d.nowS(), {truth.x(), truth.y()});
      clearance = margins.back();
      for (size_t k = 0; k < grown.size(); ++k)
        if (grown[k].check(truth, &people).hit) {
          clearance = k ? margins[k - 1] : 0.0;
          break;
        }
      path.emplace_back(float(truth.x()), float(truth.y()));
    }
    tracker.onStep(truth, d.base().velocity().vx, d.base().velocity().wz, clearance);
    if (!a.quiet && std::chrono::steady_clock::now() - last_print > std::chrono::milliseconds(tty ? 250 : 5000)) {
      last_print = std::chrono::steady_clock::now();
      fmt::print(stderr, "{}eval nav: mission {}/{}  {:.0f} s  collisions {}  {}{}", tty ? "\r" : "",
                 std::min(tracker.current() + 1, goals.size()), goals.size(), d.nowS(), d.collisions().size(),
                 loop.lastCommandStatus(), tty ? "\033[K" : "\n");
    }
  }
  if (!a.quiet && tty) fmt::print(stderr, "\n");
  // polynav reports the last goal reached for its hold time, then ends with a stop command: run
  // on until it has (30 s of simulated time at most), and read the stop, so that the loop's
  // counters say whether it was taken.
  for (const double until = loop.nowS() + 30; nav.running() && daemon.running() && loop.nowS() < until;) loop.step();
  nav.wait(5.0);
  loop.readCommands();
  nav.stop();
  daemon.stop();
  ::shm_unlink(("/polyloc." + instance).c_str());  // polylocd leaves its segment for a restart; this one is done

  // Totals.
  size_t reached = 0, collisions = 0, danger = 0, passages = 0, oscillations = 0, within = 0;
  double min_clearance = INFINITY, time_ratio_sum = 0;
  std::map<std::string, size_t> hit_what;
  std::vector<double> errors;
  for (const MissionResult& m : tracker.results()) {
    reached += m.reached;
    collisions += m.collisions.size();
    for (const auto& c : m.collisions) ++hit_what[c.contact.label.empty() ? c.contact.what : c.contact.label];
    danger += m.danger_entries;
    passages += m.door_passages, oscillations += m.door_oscillations;
    min_clearance = std::min(min_clearance, m.min_clearance_m);
    if (m.reached) {
      errors.push_back(m.goal_error_m);
      within += m.goal_error_m <= 0.02 && m.goal_yaw_error_deg <= 1.0;
      if (std::isfinite(m.optimal_m)) time_ratio_sum += m.duration() / (m.optimal_m / 0.5);
    }
  }
  std::sort(errors.begin(), errors.end());
  const double n = double(goals.size());
  nlohmann::json j{{"scenario", a.scenario}, {"vrs", a.vrs}, {"local", a.local}, {"missions", goals.size()},
                   {"reached", reached}, {"success_rate", n ? double(reached) / n : 0.0}, {"collisions", collisions},
                   {"collisions_by_label", hit_what}, {"danger_entries", danger}, {"door_passages", passages},
                   {"door_oscillations", oscillations},
                   {"min_clearance_m", std::isfinite(min_clearance) ? nlohmann::json(min_clearance) : nlohmann::json(nullptr)},
                   {"goal_within_2cm_1deg", within},
                   {"goal_error_max_m", errors.empty() ? nlohmann::json(nullptr) : nlohmann::json(errors.back())},
                   {"time_vs_optimal", reached ? nlohmann::json(time_ratio_sum / double(reached)) : nlohmann::json(nullptr)},
                   {"sim_s", loop.nowS()}, {"drive", driveJson(loop)}, {"per_mission", tracker.json()}};
  if (!a.plot.empty()) {
    plotRun(map, zones, path, tracker, goals,
            fmt::format("eval nav {} (vrs {}, {})", fs::path(a.scenario).filename().string(), a.vrs, a.local), a.plot);
    j["plot"] = a.plot;
  }
  if (!a.keep.empty()) {  // polylocd's poses as they came back (TUM: stamp x y z qx qy qz qw)
    std::ofstream tum(dir / "poses.tum");
    tum.precision(12);
    for (const auto& e : loop.feed().result().estimates)
      tum << double(e.stamp_ns) * 1e-9 << ' ' << e.pose.x() << ' ' << e.pose.y() << ' ' << e.pose.z() << ' ' << e.pose.yaw() << '\n';
  }
  if (a.keep.empty()) fs::remove_all(dir);
  if (a.json) fmt::print("{}\n", j.dump());
  else
    fmt::print("eval nav (vrs {}, {}): {}/{} missions reached, {} collisions, {} danger-zone entries, {} door passages "
               "({} oscillating), min clearance {:.2f} m, {} goals within 2 cm / 1 deg, time {:.2f}x the optimal\n",
               a.vrs, a.local, reached, goals.size(), collisions, danger, passages, oscillations, min_clearance, within,
               reached ? time_ratio_sum / double(reached) : 0.0);
}

}  // namespace cmd_eval_nav_impl

void registerEvalNav(CLI::App& eval) {
  using namespace cmd_eval_nav_impl;
  auto a = std::make_shared<Args>();
  CLI::App& c = *eval.add_subcommand("nav", "Navigation missions in a closed loop: polylocd + polynav + the simulated robot");
  c.add_option("--scenario", a->scenario, "Scenario with a navigation: section (maps/scenarios/lab_nav.yaml)")->required()->check(CLI::ExistingFile);
  c.add_option("--missions", a->missions, "Missions (goals visited one after the other)")->capture_default_str()->check(CLI::Range(1, 10000));
  c.add_option("--vrs", a->vrs, "on: the VRS of every sensor; off: the level scanners only (a 2D controller)")
      ->capture_default_str()->check(CLI::IsMember({"on", "off"}));
  c.add_option("--local", a->local, "The controller's local avoidance: nd or vfh")->capture_default_str()->check(CLI::IsMember({"nd", "vfh"}));
  addSeedOption(c, a->seed, "Overrides the scenario's seed (people, noise, goals drawn)");
  c.add_option("--threads", a->threads, "polylocd's TBB threads")->capture_default_str()->check(CLI::Range(1, 256));
  c.add_option("--rate", a->rate, "Pacing against the wall clock (1: real time)")->capture_default_str()->check(finiteRange(0.1, 1e6));
  c.add_option("--live-port", a->live_port, "Open the internal polylocd's live view on this port (0: none; 8765 is the usual)")
      ->capture_default_str()->check(CLI::Range(0, 65535));
  c.add_option("--plot", a->plot, "PNG: map, the robot's path, goals, collisions");
  c.add_option("--keep", a->keep, "Keep the work files (grid, polylocd config, logs) in this folder");
  c.add_flag("--json", a->json, "Results as one JSON object on stdout");
  c.add_flag("--quiet", a->quiet, "No status line");
  c.callback([a] { run(*a); });
}

}  // namespace polyloc::cli
