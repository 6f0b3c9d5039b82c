#include "pipeline/pipeline.hpp"

#include <polyloc/geometry/domain.hpp>
#include <polyloc/vrs/moving_objects.hpp>

#include <algorithm>
#include <limits>

namespace polyloc::pipeline {

Pipeline::Pipeline(const PolylocConfig& config, const Mesh& map, const RayCaster& caster, const RayCaster* weigh,
                   PipelineOptions options)
    : Pipeline(config, &map) {
  beside_ = options.search_beside;
  LocalizerWorkerConfig wc;
  wc.threaded = beside_, wc.threads = options.threads;
  wc.copy_particles = beside_ && options.keep_particles;
  wc.max_queue_bytes = options.max_queue_bytes;
  loc_ = std::make_unique<LocalizerWorker>(std::make_unique<Localizer>(caster, map, cfg_.rig, cfg_.mcl, weigh), wc);
}

Pipeline::Pipeline(const PolylocConfig& config, const Mesh* map) : cfg_(config) {
  vrs_ = std::make_unique<VirtualRangeScanner>(cfg_.rig, cfg_.robot, cfg_.vrs, map);
  people_ = std::make_unique<PeopleTracker>(cfg_.rig, cfg_.tracking);
  level_ = people_->sensors();
  // For polylocd and perceive alike: the VRS and tracks renew at the last level scanner's frames,
  // when the other scanners' frames of that instant are in.
  trigger_ = level_.empty() ? 0 : level_.back();
  filters_.resize(cfg_.rig.size());
  depth_factor_.resize(cfg_.rig.size());
  for (size_t k = 0; k < cfg_.rig.size(); ++k)
    if (const auto* cam = std::get_if<DepthCameraSpec>(&cfg_.rig.sensors[k].spec)) {
      filters_[k].emplace(*cam, cfg_.rig.sensors[k].mount, cfg_.depth_filter);
      depth_factor_[k] = cam->depthFactors();
    }
}

Pipeline::~Pipeline() = default;

// Localizer::checkPose reads only the map's box and the config, which never change: safe beside
// a worker that runs.
std::optional<std::string> Pipeline::checkPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance) const {
  if (!loc_) return "perception-only pipeline: no localiser to take a pose";
  return loc_->localizer().checkPose(map_T_base, covariance);
}

bool Pipeline::initPose(const Pose& map_T_base, const Eigen::Matrix<double, 6, 6>& covariance, int64_t stamp_ns) {
  if (!loc_ || checkPose(map_T_base, covariance)) return false;
  loc_->initPose(map_T_base, covariance, stamp_ns);
  map_T_odom_ = map_T_base * odometry_.at(stamp_ns).inverse();
  initialised_ = true;
  searching_ = false;
  return true;
}

void Pipeline::initGlobal(int64_t stamp_ns) {
  if (!loc_) return;
  loc_->initGlobal(stamp_ns);
  initialised_ = true;
  searching_ = true;
  async_ = beside_;
}

const ParticleSet* Pipeline::particles() const {
  if (particles_) return particles_.get();
  return loc_ && !beside_ ? &loc_->localizer().particles() : nullptr;
}

void Pipeline::setPose(const Pose& map_T_base) {
  if (loc_) throw std::logic_error("Pipeline::setPose: a localising pipeline takes its pose from the localiser");
  pose_ = map_T_base;
}

void Pipeline::addOdometry(int64_t stamp_ns, const Pose& odom_T_base) {
  if (!loc_) return;
  ++counters_.odometry;
  odometry_.add(stamp_ns, odom_T_base);
  loc_->addOdometry(stamp_ns, odom_T_base);
}

void Pipeline::weigh(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, uint64_t tag, PipelineSink& sink) {
  loc_->addScan(sensor, stamp_ns, ranges, tag);
  // Tracking: the frame's pose before its VRS and tracks, as inline.
  if (!async_) loc_->waitIdle();
  publish(sink);
}

void Pipeline::publish(PipelineSink& sink) {
  for (LocalizerWorker::Round& r : loc_->take()) {
    est_ = r.estimate;
    searching_ = r.searching;
    // The estimate is at the scan's stamp, so is the odometry it is paired with (odometry newer
    // than the scan may have come first): this correction holds until the next update (REP-105).
    if (domain::validPose(est_.pose) && est_.status != MclStatus::Initialising) map_T_odom_ = est_.pose * r.odom_at_stamp.inverse();
    pose_tag_ = r.tag;
    particles_ = std::move(r.particles);
    ++counters_.poses;
    sink.onPose(est_, map_T_odom_);
  }
  // The search is over and its backlog weighed: frames wait for their weighing again. Never by
  // blocking: the backlog's tracking rounds would hold the VRS up for their sum.
  if (async_ && !searching_ && loc_->idle()) {
    async_ = false;
    publish(sink);  // what ended between take() and idle()
  }
  if (!async_ && beside_ && searching_) async_ = true;  // a relocalisation started a search
}

void Pipeline::poll(PipelineSink& sink) {
  if (loc_ && initialised_) publish(sink);
}

void Pipeline::finish(PipelineSink& sink) {
  if (!loc_ || !initialised_) return;
  loc_->waitIdle();
  publish(sink);
}

bool Pipeline::addRanges(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, PipelineSink& sink, uint64_t tag) {
  if (sensor >= cfg_.rig.size() || std::holds_alternative<DepthCameraSpec>(cfg_.rig.sensors[sensor].spec) ||
      ranges.size() != cfg_.rig.sensors[sensor].beams().size()) {
    ++counters_.rejected;
    return false;
  }
  ++counters_.ranges;
  if (initialised_) weigh(sensor, stamp_ns, ranges, tag, sink);
  perceive(sensor, stamp_ns, ranges, sink);
  return true;
}

bool Pipeline::addDepth(size_t sensor, int64_t stamp_ns, const float* depth, const float* amplitude, PipelineSink& sink,
                        uint64_t tag) {
  if (sensor >= cfg_.rig.size() || !filters_[sensor] || !depth) {
    ++counters_.rejected;
    return false;
  }
  ++counters_.depth;
  if (initialised_) {  // never in perception-only mode
    // The localiser weighs ranges along the pixel rays; the camera gives depth along the axis.
    const auto& factor = depth_factor_[sensor];
    scratch_.resize(factor.size());
    for (size_t b = 0; b < factor.size(); ++b)
      scratch_[b] = factor[b] > 0 ? depth[b] / factor[b] : std::numeric_limits<float>::quiet_NaN();
    weigh(sensor, stamp_ns, scratch_, tag, sink);
  }
  if (!vrs_enabled_) return true;
  const auto& spec = filters_[sensor]->camera();
  filters_[sensor]->apply(DepthFrameView{spec.width, spec.height, depth, amplitude, nullptr}, depth_result_);
  points_.clear();
  for (size_t k = 0; k < depth_result_.x.size(); ++k) points_.emplace_back(depth_result_.x[k], depth_result_.y[k], depth_result_.z[k]);
  vrs_->addPoints(sensor, stamp_ns, poseAt(stamp_ns), points_);
  return true;
}

void Pipeline::perceive(size_t sensor, int64_t stamp_ns, std::span<const float> ranges, PipelineSink& sink) {
  const Pose pose = poseAt(stamp_ns);
  if (vrs_enabled_) vrs_->addFrame(sensor, stamp_ns, pose, ranges);
  const bool level = std::find(level_.begin(), level_.end(), sensor) != level_.end();
  if (level) people_->addScan(sensor, stamp_ns, cfg_.rig.sensors[sensor].worldPose(pose), ranges);
  if (sensor != trigger_) return;
  people_->flush();
  ++counters_.tracks;
  sink.onTracks(stamp_ns, people_->tracks());
  if (!vrs_enabled_) return;
  vrs_->setMovingObjects(movingObjects(people_->tracks()));
  const VirtualScan v = vrs_->update(stamp_ns, pose);
  ++counters_.vrs;
  sink.onVrs(v);
}

}  // namespace polyloc::pipeline
