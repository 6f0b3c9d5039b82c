// One recording (or one time segment of it) through the Monte-Carlo localiser: the per-recording
// work that `polyloc localize` and `polyloc relocalize` share (docs/relocalize.md). It reads
// the recording, starts the filter by the rules of `localize` (an explicit pose, --global, else
// the first ground-truth pose, else global), feeds odometry and range frames, and keeps every
// estimate with covariance, status and ESS. It writes nothing: the report functions do.
//
//   JobContext ctx{cfg, mesh, caster};        // shared, read-only, by concurrent jobs
//   JobResult r = runRecordingJob(ctx, options);
#pragma once

#include "reloc/topic_router.hpp"
#include "viz/localize_plot.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/eval/trajectory_metrics.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/tum.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/raycast/ray_caster.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace polyloc::reloc {

// What every job of one run shares. The caster is only read (castScans is thread-safe); the
// config's mcl section is used as is, so set mcl.threads = 0 to weigh in the caller's arena.
struct JobContext {
  const PolylocConfig& config;
  const Mesh& mesh;
  const RayCaster& caster;            // exact (Embree): floor and free space
  const RayCaster* weigh = nullptr;   // mcl.caster when not embree (mcl/weighing.hpp)
};

enum class StartMode { Auto, Global, Pose };

struct JobOptions {
  std::string input;
  // Opens the recording (default: openRecording(input)); e.g. an in-memory run of eval carmen.
  std::function<std::unique_ptr<RecordingReader>()> open;
  double restamp_hz = 0;              // > 0: every message restamped by its order (io/restamp.hpp)
  StartMode start = StartMode::Auto;  // Auto: first ground-truth pose (of the read span), else global
  Pose start_pose;                    // StartMode::Pose
  double init_sigma_xy_m = 0.1, init_sigma_yaw_deg = 5;  // spread of pose and ground-truth starts
  std::vector<bool> sensors;          // per rig sensor, used or not; empty = all
  std::string ground_truth_file;      // TUM; empty: the recording's /ground_truth
  // Time window (log time, ns). Messages before read_from_ns are skipped (a segment's warm-up
  // starts there); estimates outside [keep_from_ns, keep_to_ns) are not kept. Defaults: all.
  int64_t read_from_ns = std::numeric_limits<int64_t>::min();
  int64_t keep_from_ns = std::numeric_limits<int64_t>::min();
  int64_t keep_to_ns = std::numeric_limits<int64_t>::max();
  size_t stop_after_updates = 0;      // > 0: stop reading after this many measurement updates
  bool plot = false;                  // collect the paths and particle clouds for the PNG
  size_t plot_particles = 500;        // particles per cloud in the plot
  // Progress, fraction 0..1 of the span to read, called every ~64 messages (from this thread).
  std::function<void(double fraction, uint64_t updates)> progress;
  // Warnings (once per kind) and notes as they come, without the "polyloc ...:" prefix.
  std::function<void(const std::string&)> log;
  // Live hooks (polyloc localize --live), from this thread: each range frame the filter takes,
  // and each measurement update with the particles and the odometry at the estimate's stamp.
  std::function<void(size_t sensor, int64_t stamp_ns, std::span<const float> ranges)> on_frame;
  std::function<void(const MclEstimate&, const ParticleSet&, const Pose& odom_T_base)> on_update;
};

// One kept estimate: what the per-frame CSV and the TUM file hold.
struct FrameRecord {
  int64_t stamp_ns = 0;
  Pose pose;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  MclStatus status = MclStatus::Initialising;
  double ess = 0;
  size_t particles = 0;
  double seen_through = 0;            // share of the round's beams beyond the map's surface (mcl.fit)
  bool refined = false;               // the estimate was refined against the mesh (mcl.refine)
  double map_fit = -1;                // share of the beams the map explains, smoothed (mcl.fit; -1: not yet)
};

struct JobResult {
  std::string input, format;
  Rig rig;                            // the rig used: the config's, completed from the recording when it asks
  std::string init_mode = "global";   // "global", "pose", "ground_truth"
  int64_t init_ns = 0;                // when the filter started (0: never)
  int64_t keep_from_ns = 0, keep_to_ns = 0;  // the kept span as given (for the merge)
  std::vector<FrameRecord> frames;    // kept estimates, in stamp order
  std::vector<StampedPose> truth;     // ground truth over the read span (file or stream)
  bool truth_from_stream = true;
  std::map<std::string, uint64_t> counters;  // the `counters` object of the JSON summary
  uint64_t updates = 0;
  size_t final_particles = 0;
  MclStatus final_status = MclStatus::Initialising;
  Pose final_pose;
  double final_range_bias = 0;        // m (mcl.range_bias)
  double final_odometry_scale_translation = 1, final_odometry_scale_rotation = 1;  // mcl.motion.adapt
  double filter_s = 0, wall_s = 0;
  viz::LocalizePlotData plot;         // estimate path and clouds (truth path: see truthPath)
  std::vector<std::string> warnings;  // of the reader, first 5
  std::vector<std::string> stamp_warnings;  // stamps that do not increase, per topic (io/stamp_check.hpp)
  uint64_t stamps_bad = 0;
};

// Throws (IoError, std::runtime_error) when the input cannot be read at all.
JobResult runRecordingJob(const JobContext& ctx, const JobOptions& options);

// The recording of a job, as the job reads it (options.open or the file; restamped when asked).
std::unique_ptr<RecordingReader> openJobRecording(const JobOptions& options);

// The first /ground_truth pose at or after `from_ns` (a short pass over the recording).
std::optional<StampedPose> firstTruth(const JobOptions& options, int64_t from_ns);

// --sensors "a,b": which rig sensors are used (empty list: all). Throws naming a sensor the
// rig does not have.
std::vector<bool> sensorMask(const Rig& rig, const std::string& names);

// Estimates as the metrics take them.
std::vector<EstimatedPose> estimatesOf(const std::vector<FrameRecord>& frames);

}  // namespace polyloc::reloc
