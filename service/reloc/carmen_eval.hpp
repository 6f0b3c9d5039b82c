// The real-log evaluation behind `polyloc eval carmen` (docs/localization.md "Real logs"): a log
// with known (corrected) poses is split into map and test scans; the map is the even scans'
// occupancy grid extruded to a mesh (map/scan_mapper.hpp, map/extrude.hpp); the test run is the
// odd scans, localised by the same job as `polyloc localize` (recording_job.hpp) with the drift
// odometry and with the log's own (eval/real_log_runs.hpp); the floor is each test scan aligned
// to the mesh around its known pose (eval/scan_alignment.hpp); global localisation starts from a
// uniform prior at random test frames.
//
//   CarmenEvalOptions o;  o.log = "../shared/data/carmen/aces-corrected.log.gz";
//   CarmenEvalResult r = runCarmenEval(o);
//   r.floor.ate_rmse_m, r.variants[0].metrics->all.ate_rmse_m, r.global ...
#pragma once

#include "reloc/recording_job.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/eval/real_log.hpp>
#include <polyloc/eval/real_log_runs.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>
#include <polyloc/map/extrude.hpp>
#include <polyloc/map/grid_map.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/map/scan_mapper.hpp>

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
  size_t every = 2;                // > 2: only every every-th of the odd scans is a test scan (long logs)
  OdometryDrift drift;             // seed: CarmenEvalOptions::seed
  double restamp_hz = 10;          // test runs whose stamps do not increase: by order at this rate
  ScanMapperConfig mapper;         // the map's grid (0.05 m, beams to 30 m)
  ExtrudeOptions extrude;          // walls 2 m
  std::vector<std::string> variants{"drift", "own"};
  bool floor = true;
  size_t global_trials = 20;       // 0: none
  size_t global_updates = 10;      // a trial succeeds when the estimate after this many updates ...
  double global_pos_tol = 0.3;     // ... is within this (m) ...
  double global_yaw_tol_deg = 5;   // ... and this of the truth
  uint64_t seed = 1;               // drift noise and global starts (mcl.seed is the config's)
  bool plot = false;               // collect paths and clouds for a PNG
  // Stage ("map", "floor", "drift", "own", "global") and its fraction done; called often.
  std::function<void(const std::string& stage, double fraction)> progress;
  std::function<void(const std::string&)> log_line;  // notes and warnings, as they come
};

struct CarmenVariant {
  std::string name, stamps;           // "drift" / "own"; "recorded" or how it was restamped
  std::string unusable;               // why the run was not localised ("" when it was: TestRun::unusable)
  std::shared_ptr<const std::vector<RecordedMessage>> run;  // the test run as the job read it
  JobResult job;
  std::optional<TrajectoryMetrics> metrics;
  TrajectoryMetrics odometry_only;    // the run's odometry alone, from the first truth pose
  uint64_t odometry = 0, odometry_dropped = 0;
};

struct CarmenGlobalTrial {
  size_t test_index = 0;              // the start, index into the test scans
  Pose truth;                         // truth at the last update
  Pose estimate;
  double pos_err = 0, yaw_err_deg = 0;  // after the last update
  size_t updates = 0;
  int first_within = -1;              // 1-based update from which every estimate is within tolerance, or -1
  bool success = false;
  double filter_s = 0;
};

struct CarmenEvalResult {
  std::string log, topic, geometry;   // geometry: describeGeometry of the first scan
  size_t scans = 0, map_scans = 0, test_scans = 0;
  uint64_t log_odometry = 0, rejected_lines = 0;
  OccupancyGrid grid;
  Mesh mesh;
  PolylocConfig config;
  std::vector<StampedPose> truth;     // the test scans' known poses (drift run stamps)
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
  std::vector<CarmenVariant> variants;
  std::vector<CarmenGlobalTrial> global;
  double map_s = 0, floor_s = 0, wall_s = 0;
};

// Throws std::runtime_error naming the file for a log without scans with poses, a bad config,
// or fewer than 2 test scans.
CarmenEvalResult runCarmenEval(const CarmenEvalOptions& options);

// The built-in config: robot.radius 0.25, `rig: recorded`, every mcl key at its default.
PolylocConfig defaultCarmenConfig();

}  // namespace polyloc::reloc
