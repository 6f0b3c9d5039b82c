// The real-log evaluation behind `polyloc eval carmen` (docs/localization.md "Real logs"): a log
// with known (corrected) poses is split into map and test scans; the map is built from the even
// scans in one or more styles (eval/real_log_maps.hpp: polyloc's extrusion, end-point cells,
// coarse cells, dilated walls, noisy walls); the test run is the odd scans, localised by the same
// job as `polyloc localize` (recording_job.hpp) with drift odometry of one or more levels
// (eval/real_log_runs.hpp), every scan or every 2nd, 4th ... of them, and with the log's own
// odometry; the floor is each test scan aligned to each map around its known pose
// (eval/scan_alignment.hpp); global localisation starts from a uniform prior at random test frames.
// Each (map style, drift, decimation) is a case of the robustness matrix.
//
//   CarmenEvalOptions o;  o.log = "../shared/data/carmen/aces-corrected.log.gz";
//   o.map_styles = {"polyloc", "endpoint"};  o.drifts = {parseDrift("mid"), parseDrift("high")};
//   CarmenEvalResult r = runCarmenEval(o);
//   r.cases[i].metrics->all.ate_rmse_m / r.cases[i].floor->all.ate_rmse_m, r.maps[0].global ...
#pragma once

#include "reloc/recording_job.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/eval/estimate_consistency.hpp>
#include <polyloc/eval/real_log.hpp>
#include <polyloc/eval/real_log_maps.hpp>
#include <polyloc/eval/real_log_runs.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::reloc {

struct CarmenEvalOptions {
  std::string log;
  std::string topic;               // scan topic ("" = the log's first laser with poses)
  std::string config;              // polyloc config ("" = the defaults: robot.radius 0.25, rig recorded)
  std::vector<std::string> map_styles{"polyloc"};      // logMapStyles()
  std::vector<OdometryDrift> drifts{parseDrift("mid")};  // their seeds: CarmenEvalOptions::seed
  std::vector<size_t> decimations{1};  // 1: every test scan, 2: every 2nd, ...
  size_t test_scans = 0;           // > 0: only the first this many test scans (a prefix: tests)
  bool own = true;                 // also the log's own odometry (first map style, every test scan)
  double restamp_hz = 10;          // test runs whose stamps do not increase: by order at this rate
  LogMapOptions map;               // cells 5 cm (coarse: 10), beams to 30 m, walls 2 m
  bool floor = true;
  size_t global_trials = 20;       // per map style (0: none)
  size_t global_updates = 10;      // a trial succeeds when the estimate after this many updates ...
  double global_pos_tol = 0.3;     // ... is within this (m) ...
  double global_yaw_tol_deg = 5;   // ... and this of the truth
  uint64_t seed = 1;               // drift noise, noisy maps and global starts (mcl.seed is the config's)
  bool plot = false;               // collect paths and clouds for a PNG
  // Stage ("map polyloc", "floor polyloc", "polyloc mid x1", "global polyloc") and its fraction done.
  std::function<void(const std::string& stage, double fraction)> progress;
  std::function<void(const std::string&)> log_line;  // notes and warnings, as they come
};

struct CarmenGlobalTrial {
  size_t test_index = 0;              // the start, index into the test scans
  Pose truth;                         // truth at the last update
  Pose estimate;
  double pos_err = 0, yaw_err_deg = 0;  // after the last update
  size_t updates = 0;
  int first_within = -1;              // 1-based update from which every estimate is within tolerance, or -1
  size_t tracking_beyond_0_5m = 0;    // updates published `tracking` more than 0.5 m from the truth (never confidently wrong)
  bool success = false;
  double filter_s = 0;
};

// One map style: the map, the floor it allows, what the fit check sees on it, global trials.
struct CarmenMap {
  LogMap map;
  std::vector<Pose> aligned;          // per test scan: its scan aligned to the map around the known pose
  double range_bias = 0;              // m: the map's (median over the test scans; the floor takes it off)
  std::optional<TrajectoryMetrics> floor;  // the aligned poses against the known ones
  size_t floor_refined = 0;           // of the test scans, the refinement accepted
  std::map<std::string, size_t> floor_refused;  // the others, by reason
  // The fit check (mcl/fit_check.hpp) on the test scans: share of beams seen through the map at
  // the aligned pose, and at poses displaced from it by 0.5 m and 2 m (random direction, yaw
  // +-10 deg): what mcl.fit.max_seen_through must separate.
  std::vector<double> seen_through_aligned, seen_through_0_5m, seen_through_2m;
  std::vector<double> explained_aligned;  // share of beams the map explains at the aligned pose (map fit)
  // Per test scan: the aligned position's std along the scanner's heading (m; inf when the
  // refinement was refused). Large in corridors: there the scan leaves the position open.
  std::vector<double> floor_std_along;
  std::vector<CarmenGlobalTrial> global;
  double map_s = 0, floor_s = 0;
};

// One run of the matrix: a map style, an odometry, a decimation.
struct CarmenCase {
  std::string map_style;
  size_t map = 0;                     // index into CarmenEvalResult::maps
  std::string odometry;               // "own", or the drift's name
  OdometryDrift drift;                // when odometry is a drift
  size_t decimate = 1;
  std::vector<size_t> test_positions; // the run's scans as indices into the test scans (truth order)
  std::string stamps;                 // "recorded" or how it was restamped
  std::string unusable;               // why the run was not localised ("" when it was: TestRun::unusable)
  std::shared_ptr<const std::vector<RecordedMessage>> run;  // the test run as the job read it
  JobResult job;
  std::optional<TrajectoryMetrics> metrics;
  std::optional<TrajectoryMetrics> floor;  // the map's floor on this run's scans
  TrajectoryMetrics odometry_only;    // the run's odometry alone, from the first truth pose
  Consistency consistency;            // status and covariance against the truth
  uint64_t odometry_messages = 0, odometry_dropped = 0;
  std::string name() const;           // "polyloc/mid/x1", "polyloc/own/x1"
};

struct CarmenEvalResult {
  std::string log, topic, geometry;   // geometry: describeGeometry of the first scan
  size_t scans = 0, map_scans = 0, test_scans = 0;
  uint64_t log_odometry = 0, rejected_lines = 0;
  PolylocConfig config;
  std::vector<StampedPose> truth;     // the test scans' known poses (at the first drift run's stamps)
  std::vector<CarmenMap> maps;        // in the order of CarmenEvalOptions::map_styles
  // Map style-major, then drift, then decimation; the own run after the first map style's.
  std::vector<CarmenCase> cases;
  double wall_s = 0;
};

// Throws std::runtime_error naming the file for a log without scans with poses, a bad config,
// or fewer than 2 test scans; std::invalid_argument for an unknown map style.
CarmenEvalResult runCarmenEval(const CarmenEvalOptions& options);

// The built-in config: robot.radius 0.25, `rig: recorded`, every mcl key at its default.
PolylocConfig defaultCarmenConfig();

}  // namespace polyloc::reloc
