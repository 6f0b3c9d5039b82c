#include "pipeline/control.hpp"

#include "pipeline/seed_check.hpp"
#include "pipeline/shm_payloads.hpp"

#include <polyloc/geometry/domain.hpp>
#include <spdlog/spdlog.h>

#include <cmath>
#include <limits>

namespace polyloc::pipeline {

DaemonControl::DaemonControl(LiveState& live, const ServiceConfig& config, std::vector<std::string> input_names,
                             const Eigen::AlignedBox3f& map)
    : live_(live), cfg_(config), inputs_(std::move(input_names)), map_(map) {
  const Rig& rig = cfg_.polyloc.rig;
  for (size_t k = 0; k < rig.size(); ++k)
    if (std::holds_alternative<PlanarScannerSpec>(rig.sensors[k].spec)) scanners_.push_back(k);
  vrs_segments_ = uint32_t(cfg_.polyloc.vrs.segments());
}

std::optional<protocol::PoseReport> DaemonControl::pose() {
  const auto s = live_.snapshot();
  if (!s.pose) return std::nullopt;
  const polyloc_pose& p = *s.pose;
  protocol::PoseReport r;
  r.stamp_ns = p.stamp_ns;
  r.pose = posePose(p);
  for (int i = 0; i < 36; ++i) r.covariance(i / 6, i % 6) = p.covariance[i];
  r.status = static_cast<protocol::PoseStatus>(std::min<uint32_t>(p.status, 3));
  r.ess = p.ess;
  r.particles = p.particles;
  return r;
}

protocol::Status DaemonControl::setPose(const protocol::PoseSeed& seed) {
  // The defaults of a seed without spreads: polylocd.init's, else 0.1 m and 5 deg.
  const InitPose def = cfg_.daemon.init.value_or(InitPose{});
  const double sxy = seed.sigma_xy_m.value_or(def.sigma_xy), syaw = seed.sigma_yaw_rad.value_or(def.sigma_yaw);
  if (const auto why = seedProblem(seed, sxy, syaw, map_)) {
    spdlog::warn("SETPOSE refused: {} (the map covers {})", *why, domain::describeArea(map_));
    return protocol::Status::BadArgument;
  }
  PoseRequest r;
  r.pose = seed.pose();
  r.covariance = Eigen::Matrix<double, 6, 6>::Zero();
  r.covariance.diagonal() << sxy * sxy, sxy * sxy, 0.02 * 0.02, 3e-4, 3e-4, syaw * syaw;
  live_.requestPose(r);
  return protocol::Status::Ok;
}

protocol::Status DaemonControl::globalLocalization() {
  live_.requestGlobal();
  return protocol::Status::Ok;
}

std::vector<protocol::ScannerInfo> DaemonControl::scanners() {
  std::vector<protocol::ScannerInfo> out{{"vrs", Pose(), vrs_segments_}};
  for (size_t k : scanners_) {
    const Sensor& s = cfg_.polyloc.rig.sensors[k];
    out.push_back({s.name, s.mount, uint32_t(s.beams().size())});
  }
  return out;
}

std::optional<protocol::PolarScan> DaemonControl::scan(uint32_t index) {
  const auto s = live_.snapshot();
  const std::optional<LiveScan>* ls = nullptr;
  if (index == 0) ls = &s.vrs;
  else if (index - 1 < scanners_.size()) ls = &s.scans[scanners_[index - 1]];
  if (!ls || !*ls) return std::nullopt;
  protocol::PolarScan p;
  p.stamp_ns = (*ls)->stamp_ns;
  const auto& r = (*ls)->ranges;
  p.angles.resize(r.size());
  p.ranges.resize(r.size());
  for (size_t i = 0; i < r.size(); ++i) {
    p.angles[i] = (*ls)->angle_min + float(i) * (*ls)->angle_increment;
    // No return (NaN, inf, out of the scanner's window): +inf, as the protocol says.
    const bool valid = std::isfinite(r[i]) && r[i] >= (*ls)->range_min && r[i] <= (*ls)->range_max;
    p.ranges[i] = valid ? r[i] : std::numeric_limits<float>::infinity();
  }
  return p;
}

bool DaemonControl::collisionAvoidance() { return live_.collisionAvoidance(); }
void DaemonControl::setCollisionAvoidance(bool on) { live_.setCollisionAvoidance(on); }

protocol::TrackList DaemonControl::tracks() {
  const auto s = live_.snapshot();
  protocol::TrackList t;
  t.stamp_ns = s.tracks_stamp_ns;
  for (const polyloc_track& k : s.tracks)
    t.tracks.push_back({k.id, k.status == 1, k.x, k.y, k.vx, k.vy, {k.covariance[0], k.covariance[1], k.covariance[2], k.covariance[3]}});
  return t;
}

protocol::HealthReport DaemonControl::health() {
  const auto s = live_.snapshot();
  const auto now = std::chrono::steady_clock::now();
  protocol::HealthReport r;
  r.uptime_s = std::chrono::duration<double>(now - start_).count();
  if (s.pose) r.pose_status = static_cast<protocol::PoseStatus>(std::min<uint32_t>(s.pose->status, 3));
  if (!s.health) return r;
  const polyloc_health& h = *s.health;
  r.stamp_ns = h.stamp_ns;
  r.cycles = h.cycles, r.poses = h.poses, r.vrs = h.vrs, r.tracks = h.tracks;
  r.cycle_p50_ms = h.cycle_p50_ms, r.cycle_p99_ms = h.cycle_p99_ms;
  std::lock_guard l(m_);
  const double dt = prev_ ? std::chrono::duration<double>(now - prev_time_).count() : 0.0;
  if (dt > 0) r.pose_rate_hz = double(h.poses - prev_->poses) / dt;
  for (uint32_t i = 0; i < h.inputs && i < inputs_.size(); ++i) {
    const polyloc_input_health& x = h.input[i];
    protocol::InputStatus in;
    in.name = inputs_[i];
    in.taken = x.taken;
    in.rejected = rejectedFrames(x);
    in.silent = x.silent != 0;
    if (dt > 0) in.rate_hz = double(x.taken - prev_->input[i].taken) / dt;
    if (x.last_stamp_ns) in.silence_s = std::max(0.0, double(h.stamp_ns - x.last_stamp_ns) * 1e-9);
    if (x.map_fit_permille > 0) in.map_fit = double(x.map_fit_permille) / 1000.0;
    r.inputs.push_back(in);
  }
  r.unfit = (h.flags & 4u) != 0;
  // Rates over at least a second: a client polling fast would otherwise see 0 or noise.
  if (!prev_ || std::chrono::duration<double>(now - prev_time_).count() > 1.0) prev_ = h, prev_time_ = now;
  return r;
}

}  // namespace polyloc::pipeline
