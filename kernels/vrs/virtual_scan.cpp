#include <polyloc/vrs/virtual_scan.hpp>

#include <polyloc/geometry/domain.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <variant>

namespace polyloc {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Planar scanners tilted by less than this are "horizontal": direct by default.
constexpr double kLevel = 0.087;  // 5 deg

VrsMode defaultMode(const Sensor& s) {
  if (std::holds_alternative<DepthCameraSpec>(s.spec)) return VrsMode::Both;
  if (std::holds_alternative<LidarSpec>(s.spec)) return VrsMode::Direct;
  const bool level = std::abs(s.mount.roll()) < kLevel && std::abs(s.mount.pitch()) < kLevel;
  return level ? VrsMode::Direct : VrsMode::Both;
}

bool usesDirect(VrsMode m) { return m == VrsMode::Direct || m == VrsMode::Both; }
bool usesMemory(VrsMode m) { return m == VrsMode::Memory || m == VrsMode::Both; }

}  // namespace

VirtualRangeScanner::VirtualRangeScanner(const Rig& rig, const RobotSpec& robot, const VrsConfig& config, const Mesh* map)
    : config_(config), rig_(rig), memory_(config.memory),
      danger_(map, config.danger_labels, config.danger_zones, config.danger_resolution) {
  if (!(config_.resolution > 0) || !(config_.angle_max > config_.angle_min) || config_.angle_max - config_.angle_min > 2 * M_PI + 1e-9)
    throw std::invalid_argument("vrs: need resolution > 0 and angle_min < angle_max <= angle_min + 360 deg");
  segments_ = config_.segments();
  for (const Sensor& s : rig_.sensors) beams_.push_back(s.beams()), modes_.push_back(defaultMode(s));
  for (const VrsSource& src : config_.sources) {
    auto it = std::find_if(rig_.sensors.begin(), rig_.sensors.end(), [&](const Sensor& s) { return s.name == src.sensor; });
    if (it == rig_.sensors.end()) throw std::invalid_argument("vrs: source '" + src.sensor + "' is not a sensor of rig '" + rig_.name + "'");
    modes_[size_t(it - rig_.sensors.begin())] = src.mode;
  }
  frames_.resize(rig_.size() + config_.cones.size());
  for (size_t k = 0; k < rig_.size(); ++k) frames_[k].mode = modes_[k];
  for (size_t k = 0; k < config_.cones.size(); ++k) frames_[rig_.size() + k].mode = config_.cones[k].mode;
  // The robot's own outline, grown by self_margin: points inside are its body (or its sensors).
  if (robot.footprint.size() >= 3) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& v : robot.footprint) c += v;
    c /= double(robot.footprint.size());
    for (const auto& v : robot.footprint) {
      const Eigen::Vector2d d = v - c;
      const double n = d.norm();
      const Eigen::Vector2d out = n > 0 ? Eigen::Vector2d(v + d / n * config_.self_margin) : v;
      body_.push_back(out.cast<float>());
    }
  } else {
    body_radius_ = float(robot.radius + config_.self_margin);
  }
  direct_.resize(segments_), plain_.resize(segments_), far_.resize(segments_);
}

bool VirtualRangeScanner::inBody(float x, float y) const {
  if (body_.empty()) return x * x + y * y < body_radius_ * body_radius_;
  bool in = false;
  for (size_t k = 0, l = body_.size() - 1; k < body_.size(); l = k++) {
    const auto &a = body_[k], &b = body_[l];
    if ((a.y() > y) != (b.y() > y) && x < (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
  }
  return in;
}

bool VirtualRangeScanner::nearMoving(const Eigen::Vector2f& p, int64_t stamp) const {
  const double s2 = config_.memory.track_sigmas * config_.memory.track_sigmas;
  const double r2 = config_.memory.track_radius * config_.memory.track_radius;
  for (size_t k = 0; k < moving_.size(); ++k) {
    const MovingObject& m = moving_[k];
    const Eigen::Vector2d d = p.cast<double>() - (m.position + m.velocity * (double(stamp - m.stamp_ns) * 1e-9));
    if (d.squaredNorm() < r2 || d.dot(moving_info_[k] * d) < s2) return true;
  }
  return false;
}

void VirtualRangeScanner::store(Frame& f, int64_t stamp, const Pose& map_T_base, const Pose& base_T_source,
                                std::span<const Eigen::Vector3f> pts) {
  const Eigen::Matrix4f T = (map_T_base * base_T_source).matrix().cast<float>();
  f.points.clear();
  for (const Eigen::Vector3f& p : pts) f.points.push_back(T.topLeftCorner<3, 3>() * p + T.topRightCorner<3, 1>());
  f.stamp = stamp;
  f.fresh = true;
  ++counters_.frames;
}

bool VirtualRangeScanner::addFrame(size_t sensor, int64_t stamp, const Pose& map_T_base, std::span<const float> ranges) {
  if (sensor >= rig_.size() || ranges.size() != beams_[sensor].size() || !domain::validPose(map_T_base))
    return ++counters_.frames_rejected, false;
  if (frames_[sensor].mode == VrsMode::Off) return false;
  const BeamSet& b = beams_[sensor];
  const Pose& mount = rig_.sensors[sensor].mount;
  const Eigen::Matrix3f R = mount.rotation().toRotationMatrix().cast<float>();
  const float h = float(mount.z()), keep = 1.f - float(config_.floor_range_margin);
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(ranges.size());
  for (size_t i = 0; i < ranges.size(); ++i) {
    const float r = ranges[i];
    if (!std::isfinite(r) || r < b.range_min || r >= b.range_max) continue;  // no return, or max-range
    // A beam going down that ends about where it meets the floor plane hit the floor.
    const float dz = R(2, 0) * b.dx[i] + R(2, 1) * b.dy[i] + R(2, 2) * b.dz[i];
    if (dz < -0.1f && h > 0 && r >= keep * h / -dz) continue;
    pts.emplace_back(b.dx[i] * r, b.dy[i] * r, b.dz[i] * r);
  }
  store(frames_[sensor], stamp, map_T_base, rig_.sensors[sensor].mount, pts);
  return true;
}

bool VirtualRangeScanner::addPoints(size_t sensor, int64_t stamp, const Pose& map_T_base, std::span<const Eigen::Vector3f> pts) {
  if (sensor >= rig_.size() || !domain::validPose(map_T_base)) return ++counters_.frames_rejected, false;
  if (frames_[sensor].mode == VrsMode::Off) return false;
  std::vector<Eigen::Vector3f> ok;
  ok.reserve(pts.size());
  for (const auto& p : pts)
    if (p.allFinite()) ok.push_back(p);
  store(frames_[sensor], stamp, map_T_base, Pose(), ok);
  return true;
}

bool VirtualRangeScanner::addCone(size_t cone, int64_t stamp, const Pose& map_T_base, float range) {
  if (cone >= config_.cones.size() || !domain::validPose(map_T_base)) return ++counters_.frames_rejected, false;
  const VrsCone& c = config_.cones[cone];
  std::vector<Eigen::Vector3f> pts;
  if (std::isfinite(range) && range >= c.range_min && range < c.range_max) {
    // The cone's cap at the measured range, filled with points: the echo may come from anywhere
    // in the cone, and the nearest possible place is what the robot must avoid.
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(c.yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(c.pitch, Eigen::Vector3d::UnitY())).toRotationMatrix();
    // Per azimuth step (half a VRS segment) the axis plane and the rim above and below: that
    // covers every segment the cone spans, with its nearest points.
    const double step = 0.5 * config_.resolution;
    for (double az = -c.half_angle; az <= c.half_angle + 1e-9; az += step) {
      const double el = std::sqrt(std::max(0.0, c.half_angle * c.half_angle - az * az));
      for (double e : {-el, 0.0, el}) {
        const Eigen::Vector3d d(std::cos(az) * std::cos(e), std::sin(az) * std::cos(e), std::sin(e));
        pts.push_back((c.position + R * (range * d)).cast<float>());
      }
    }
  }
  store(frames_[rig_.size() + cone], stamp, map_T_base, Pose(), pts);
  return true;
}

void VirtualRangeScanner::setMovingObjects(std::span<const MovingObject> objects) {
  // Sets of the last memory.delay + 1 s are kept: a waiting candidate is tested against the set
  // nearest its own time (moving along a curve, a track moved back in a line drifts off), and
  // against later ones (the tracker confirms a person some frames after they were first seen).
  int64_t newest = std::numeric_limits<int64_t>::min();
  for (const auto& m : objects) newest = std::max(newest, m.stamp_ns);
  const int64_t keep = int64_t((config_.memory.delay + 1.0) * 1e9);
  size_t kept = 0;
  for (size_t k = 0; k < moving_.size(); ++k)
    if (!objects.empty() && newest != 0 && moving_[k].stamp_ns != 0 && moving_[k].stamp_ns >= newest - keep &&
        moving_[k].stamp_ns < newest)
      moving_[kept] = moving_[k], moving_info_[kept] = moving_info_[k], ++kept;
  moving_.resize(kept), moving_info_.resize(kept);
  for (const auto& m : objects) {
    Eigen::Matrix2d c = m.covariance;
    if (!c.allFinite() || c.determinant() <= 1e-12) c = Eigen::Matrix2d::Identity() * 1e-4;
    moving_.push_back(m);
    moving_info_.push_back(c.inverse());
  }
}

VirtualScan VirtualRangeScanner::update(int64_t stamp, const Pose& map_T_base) {
  VirtualScan out;
  out.stamp_ns = stamp;
  out.map_T_base = map_T_base;
  out.angle_min = float(config_.angle_min);
  out.angle_increment = float(config_.resolution);
  out.range_max = float(config_.range_max);
  out.ranges.assign(segments_, kInf);
  out.source.assign(segments_, kVrsNone);
  out.ranges_max.assign(segments_, kInf);
  if (!domain::validPose(map_T_base)) return ++counters_.frames_rejected, out;
  ++counters_.updates;

  // Motion clock of the memory: runs only while the robot moves or turns.
  if (updated_ && stamp > last_update_) {
    const double dt = double(stamp - last_update_) * 1e-9;
    const Pose d = last_pose_.inverse() * map_T_base;
    memory_.advance(dt, d.translation().head<2>().norm() / dt, std::abs(d.yaw()) / dt);
  }
  updated_ = true, last_update_ = stamp, last_pose_ = map_T_base;

  const Eigen::Matrix4f base_T_map = map_T_base.inverse().matrix().cast<float>();
  const float zlo = float(config_.floor_clearance), zhi = float(config_.robot_height), rmax = float(config_.range_max);
  const float a0 = float(config_.angle_min), inc = float(config_.resolution);
  const int64_t max_age = int64_t(config_.max_age * 1e9);
  // The segment of a map point seen from the robot; -1 outside the band, the body or the range.
  const float two_pi = float(2 * M_PI);
  auto segment = [&](const Eigen::Vector3f& pm, float& r) -> int32_t {
    const Eigen::Vector3f p = base_T_map.topLeftCorner<3, 3>() * pm + base_T_map.topRightCorner<3, 1>();
    if (p.z() < zlo || p.z() > zhi) return -1;
    r = std::sqrt(p.x() * p.x() + p.y() * p.y());
    if (r > rmax || inBody(p.x(), p.y())) return -1;
    float a = std::atan2(p.y(), p.x()) - a0;
    if (a < 0) a += two_pi;
    if (a >= two_pi) a -= two_pi;
    const auto i = int32_t(a / inc);
    return i >= 0 && size_t(i) < segments_ ? i : -1;
  };

  // Each frame's points into segments once; the direct pass, then the memory filters.
  std::fill(direct_.begin(), direct_.end(), kInf);
  std::fill(plain_.begin(), plain_.end(), kInf);
  std::fill(far_.begin(), far_.end(), -kInf);
  const bool memory_on = config_.memory.enabled;
  for (Frame& f : frames_) {
    const bool direct = usesDirect(f.mode) && stamp - f.stamp <= max_age;
    const bool memory = memory_on && usesMemory(f.mode) && f.fresh;
    f.seg.clear(), f.range.clear();
    if (!direct && !memory) continue;
    f.seg.resize(f.points.size()), f.range.resize(f.points.size());
    for (size_t k = 0; k < f.points.size(); ++k) f.seg[k] = segment(f.points[k], f.range[k]);
    if (!direct) continue;
    for (size_t k = 0; k < f.points.size(); ++k) {
      if (f.seg[k] < 0) continue;
      const auto i = size_t(f.seg[k]);
      const float r = f.range[k];
      direct_[i] = std::min(direct_[i], r);
      far_[i] = std::max(far_[i], r);
      if (f.mode == VrsMode::Direct) plain_[i] = std::min(plain_[i], r);
    }
  }
  // Memory filters (thesis 6.2.2): a point enters only if it is nearer than what the direct-only
  // sources (horizontal scanners) see in its segment, within max_distance, in the height band
  // (segment() above), and, after memory.delay, not on a tracked person.
  if (memory_on) {
    const float reach = float(config_.memory.max_distance), margin = float(config_.memory.direct_margin);
    for (Frame& f : frames_) {
      if (!usesMemory(f.mode) || !f.fresh || f.seg.size() != f.points.size()) continue;
      f.fresh = false;
      for (size_t k = 0; k < f.points.size(); ++k) {
        if (f.seg[k] < 0) continue;
        const float r = f.range[k];
        if (r > reach) { ++counters_.memory_far; continue; }
        if (!(r < plain_[size_t(f.seg[k])] - margin)) { ++counters_.memory_behind; continue; }
        pending_.push_back({f.points[k].head<2>(), f.stamp});
      }
    }
    // Candidates old enough enter unless a track claims them now (a person is seen a few frames
    // before the tracker confirms them).
    const int64_t delay = int64_t(config_.memory.delay * 1e9);
    size_t kept = 0;
    for (const Pending& c : pending_) {
      if (stamp - c.stamp < delay) {
        pending_[kept++] = c;
        continue;
      }
      if (!moving_.empty() && nearMoving(c.point, c.stamp)) {
        ++counters_.memory_moving;
        continue;
      }
      memory_.insert(c.point);
      ++counters_.memory_inserted;
    }
    pending_.resize(kept);
  }
  const Eigen::Vector2f origin = map_T_base.translation().head<2>().cast<float>();
  const float yaw = float(map_T_base.yaw());
  for (size_t i = 0; i < segments_; ++i) {
    float r = direct_[i];
    uint8_t src = std::isfinite(r) ? kVrsDirect : kVrsNone;
    const float angle = yaw + out.angleOf(i);
    if (config_.memory.enabled) {
      const float m = memory_.castRay(origin, angle, std::min(r, rmax));
      if (m < r) r = m, src = kVrsMemory;
      else if (m == r && std::isfinite(m)) src |= kVrsMemory;
    }
    if (!danger_.empty()) {
      const float d = danger_.castRay(origin, angle, std::min(r, rmax));
      if (d < r) r = d, src = kVrsDanger;
      else if (d == r && std::isfinite(d)) src |= kVrsDanger;
    }
    out.ranges[i] = r <= rmax ? r : kInf;
    out.source[i] = std::isfinite(out.ranges[i]) ? src : uint8_t(kVrsNone);
    out.ranges_max[i] = std::isfinite(far_[i]) ? far_[i] : kInf;
  }
  return out;
}

}  // namespace polyloc
