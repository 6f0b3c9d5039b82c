// The kernels composed for live frames (docs/polylocd.md, "What it does with each frame"), one
// composition for polylocd and `polyloc perceive`: odometry into the localiser's prediction; every
// range frame into the localiser, the VRS and (level scanners) people tracking; depth frames as
// ranges into the localiser and, filtered, as points into the VRS. Outputs go to a sink the moment
// they are ready: the pose first (it is what a controller waits for), then tracks and VRS. No
// I/O of its own (the caller runs it inside its TBB arena) and not thread-safe: one thread feeds
// it. With `search_beside` the localiser runs on a thread of its own (localizer_worker.hpp): while
// it tracks, each frame still waits for its weighing, so everything comes out as without it; while
// a global search runs, frames go on to the VRS and tracks at once (with the last map->odom
// correction) and the search's poses come out when its rounds end, every one, in order.
//
//   Pipeline p(config, map, caster);            // localising (polylocd)
//   p.initGlobal(t0);
//   p.addOdometry(t, odom_T_base);
//   p.addRanges(sensor, t, ranges, sink);       // sink.onPose / onTracks / onVrs
//
//   Pipeline q(config, &map);                   // perception-only (perceive): the pose is given
//   q.setPose(map_T_base);
//   q.addRanges(sensor, t, ranges, sink);       // sink.onTracks / onVrs
#pragma once

#include "pipeline/localizer_worker.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/depth/filter.hpp>
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/odometry_buffer.hpp>
#include <polyloc/raycast/ray_caster.hpp>
#include <polyloc/tracking/people_tracker.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <span>
#include <vector>

namespace polyloc::pipeline {

class PipelineSink {
 public:
  virtual ~PipelineSink() = default;
  // A measurement update ended: the estimate and the map->odom correction (REP-105).
  virtual void onPose(const MclEstimate& e, const Pose& map_T_odom) {}
  virtual void onVrs(const VirtualScan& v) {}
  virtual void onTracks(int64_t stamp_ns, const Tracks& t) {}
};

struct PipelineCounters {
  uint64_t odometry = 0, ranges = 0, depth = 0;
  uint64_t poses = 0, vrs = 0, tracks = 0;
  uint64_t rejected = 0;  // frames a kernel refused (wrong sensor kind, size): also logged by the caller
};

// How the localiser runs beside the perception (polylocd's `global_search`).
struct PipelineOptions {
  bool search_beside = false;  // the localiser on its own thread (LocalizerWorker), see above
  int threads = 0;             // that thread's TBB arena (0: all cores)
  bool keep_particles = false;  // particles() for each pose (the live view)
  size_t max_queue_bytes = LocalizerWorkerConfig{}.max_queue_bytes;
};

class Pipeline {
 public:
  // Localising: the localiser gives the pose; the VRS has the map (danger zones).
  Pipeline(const PolylocConfig& config, const Mesh& map, const RayCaster& caster, const RayCaster* weigh = nullptr,
           PipelineOptions options = {});
  // Perception-only: no localiser, the caller gives the pose (setPose). map null: the VRS works
  // without it (no danger zones), as with odometry poses, which are not in the map's frame.
  // Whatever the pipeline does not own (map, caster) must outlive it.
  Pipeline(const PolylocConfig& config, const Mesh* map);
  ~Pipeline();

  bool localizing() const { return loc_ != nullptr; }
  // The localiser runs apart (a global search with search_beside): poses lag the frames.
  bool detached() const { return async_; }

  // Localising only. False (nothing changes) for a pose or spread the localiser refuses
  // (Localizer::checkPose), and always in perception-only mode (checkPose says why).
  bool initPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance, int64_t stamp_ns);
  std::optional<std::string> checkPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance) const;
  // Localising only; ignored in perception-only mode (initialised() stays false there).
  void initGlobal(int64_t stamp_ns);
  bool initialised() const { return initialised_; }
  // Perception-only: the pose of the frames that follow, until the next call (before the first,
  // the identity). Throws std::logic_error when localising: the localiser owns the pose there.
  void setPose(const Pose& map_T_base);

  // Localising only; ignored (not counted) in perception-only mode, where setPose gives the pose.
  void addOdometry(int64_t stamp_ns, const Pose& odom_T_base);
  // Ranges of a scanner or lidar of the rig in its beam order. False: not such a sensor / size.
  // `tag` comes back as poseTag() with the pose of the round this frame ends (polylocd: the
  // frame's publish time, for the latency).
  bool addRanges(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, PipelineSink& sink, uint64_t tag = 0);
  // A depth camera's frame: depth along the optical axis (width x height of its spec), amplitude
  // nullable.
  bool addDepth(size_t sensor, int64_t stamp_ns, const float* depth, const float* amplitude, PipelineSink& sink,
                uint64_t tag = 0);
  // search_beside: the poses of rounds that ended since the last call (polylocd calls it when no
  // frame comes); finish() first waits until every frame given is weighed.
  void poll(PipelineSink& sink);
  void finish(PipelineSink& sink);
  // Of the pose being published (inside onPose) or the last: the closing frame's tag, and its
  // particles (keep_particles; null otherwise).
  uint64_t poseTag() const { return pose_tag_; }
  const ParticleSet* particles() const;
  // The last estimate published, and whether a global search was running then (health).
  const MclEstimate& estimate() const { return est_; }
  bool searching() const { return searching_; }
  LocalizerWorker::Counters workerCounters() const { return loc_ ? loc_->counters() : LocalizerWorker::Counters{}; }
  // The filter's result for the last addDepth (perceive scores it against the simulator's
  // artefacts); not renewed while the VRS is off, and overwritten by the next camera's frame.
  const DepthFilterResult& lastDepth() const { return depth_result_; }

  // Switches VRS computation and publication (SETCOLLISIONAVOIDANCE); tracks go on.
  void setVrsEnabled(bool on) { vrs_enabled_ = on; }
  bool vrsEnabled() const { return vrs_enabled_; }

  const PolylocConfig& config() const { return cfg_; }
  // Localising only (localizing()); throws std::logic_error in perception-only mode. With
  // search_beside its state may be read only after finish().
  const Localizer& localizer() const {
    if (!loc_) throw std::logic_error("Pipeline::localizer: perception-only pipeline has no localiser");
    return loc_->localizer();
  }
  // Where the robot was at a stamp: the last estimate moved by the odometry to that stamp (which
  // may be older than the newest odometry: polylocd gives odometry ahead of the frames it
  // covers); perception-only: the pose of setPose, as given (a product with an identity would
  // renormalise it).
  Pose poseAt(int64_t stamp_ns) const { return loc_ ? map_T_odom_ * odometry_.at(stamp_ns) : pose_; }
  const PipelineCounters& counters() const { return counters_; }
  const VirtualRangeScanner& vrs() const { return *vrs_; }
  const PeopleTracker& people() const { return *people_; }

 private:
  void perceive(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, PipelineSink& sink);
  void weigh(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, uint64_t tag, PipelineSink& sink);
  void publish(PipelineSink& sink);

  PolylocConfig cfg_;
  std::unique_ptr<LocalizerWorker> loc_;
  bool beside_ = false, async_ = false, searching_ = false;
  OdometryBuffer odometry_;  // the localiser's odometry, for the perception's poses
  MclEstimate est_;
  uint64_t pose_tag_ = 0;
  std::shared_ptr<const ParticleSet> particles_;
  std::unique_ptr<VirtualRangeScanner> vrs_;
  std::unique_ptr<PeopleTracker> people_;
  std::vector<size_t> level_;       // tracking scanners
  size_t trigger_ = 0;              // VRS and tracks update at this sensor's frames
  std::vector<std::optional<DepthFilter>> filters_;
  std::vector<std::vector<float>> depth_factor_;
  DepthFilterResult depth_result_;
  std::vector<float> scratch_;
  std::vector<Eigen::Vector3f> points_;
  Pose map_T_odom_;
  Pose pose_;  // perception-only: setPose's
  bool initialised_ = false, vrs_enabled_ = true;
  PipelineCounters counters_;
};

}  // namespace polyloc::pipeline
