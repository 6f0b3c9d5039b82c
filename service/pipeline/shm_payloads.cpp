#include "pipeline/shm_payloads.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>

namespace polyloc::pipeline {

polyloc_pose posePayload(const MclEstimate& e, const Pose& map_T_odom, int64_t latency_ns) {
  polyloc_pose p{};
  p.stamp_ns = e.stamp_ns;
  const auto& t = e.pose.translation();
  const auto& q = e.pose.rotation();
  p.x = t.x(), p.y = t.y(), p.z = t.z();
  p.qw = q.w(), p.qx = q.x(), p.qy = q.y(), p.qz = q.z();
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) p.covariance[r * 6 + c] = e.covariance(r, c);
  const auto& ot = map_T_odom.translation();
  const auto& oq = map_T_odom.rotation();
  const double mo[7] = {ot.x(), ot.y(), ot.z(), oq.w(), oq.x(), oq.y(), oq.z()};
  std::copy(mo, mo + 7, p.map_odom);
  p.status = static_cast<uint32_t>(e.status);  // MclStatus and POLYLOC_POSE_* share their order
  p.particles = static_cast<uint32_t>(e.particles);
  p.ess = e.ess;
  p.updates = e.updates;
  p.latency_ns = latency_ns;
  return p;
}

uint32_t vrsPayload(const VirtualScan& v, bool enabled, std::vector<uint8_t>& out) {
  polyloc_vrs h{};
  h.stamp_ns = v.stamp_ns;
  h.angle_min = v.angle_min + 0.5f * v.angle_increment;  // as LaserScan: the first ray, a segment's centre
  h.angle_increment = v.angle_increment;
  h.range_min = v.range_min, h.range_max = v.range_max;
  h.count = static_cast<uint32_t>(v.ranges.size());
  h.enabled = enabled ? 1 : 0;
  const size_t bytes = offsetof(polyloc_vrs, ranges) + v.ranges.size() * sizeof(float);
  out.resize(bytes);
  std::memcpy(out.data(), &h, offsetof(polyloc_vrs, ranges));
  std::memcpy(out.data() + offsetof(polyloc_vrs, ranges), v.ranges.data(), v.ranges.size() * sizeof(float));
  return static_cast<uint32_t>(bytes);
}

polyloc_tracks tracksPayload(int64_t stamp_ns, const Tracks& t) {
  polyloc_tracks p{};
  p.stamp_ns = stamp_ns;
  for (int pass = 0; pass < 2; ++pass)
    for (const TrackState& s : t.items) {
      const bool confirmed = s.status == TrackStatus::Confirmed;
      if (s.status == TrackStatus::Deleted || confirmed != (pass == 0) || p.count == POLYLOC_MAX_TRACKS) continue;
      polyloc_track& k = p.tracks[p.count++];
      k.id = s.id, k.status = confirmed ? 1 : 0;
      k.x = s.position.x(), k.y = s.position.y(), k.vx = s.velocity.x(), k.vy = s.velocity.y();
      k.covariance[0] = s.position_cov(0, 0), k.covariance[1] = s.position_cov(0, 1);
      k.covariance[2] = s.position_cov(1, 0), k.covariance[3] = s.position_cov(1, 1);
    }
  return p;
}

Pose odometryPose(const polyloc_odometry& o) {
  return Pose(Eigen::Quaterniond(o.qw, o.qx, o.qy, o.qz).normalized(), Eigen::Vector3d(o.x, o.y, o.z));
}

polyloc_odometry odometryPayload(int64_t stamp_ns, const Pose& odom_T_base) {
  polyloc_odometry o{};
  o.stamp_ns = stamp_ns;
  const auto& t = odom_T_base.translation();
  const auto& q = odom_T_base.rotation();
  o.x = t.x(), o.y = t.y(), o.z = t.z();
  o.qw = q.w(), o.qx = q.x(), o.qy = q.y(), o.qz = q.z();
  return o;
}

Pose posePose(const polyloc_pose& p) {
  return Pose(Eigen::Quaterniond(p.qw, p.qx, p.qy, p.qz).normalized(), Eigen::Vector3d(p.x, p.y, p.z));
}

Pose mapOdomPose(const polyloc_pose& p) {
  const double* m = p.map_odom;  // x y z qw qx qy qz, as posePayload writes it
  return Pose(Eigen::Quaterniond(m[3], m[4], m[5], m[6]).normalized(), Eigen::Vector3d(m[0], m[1], m[2]));
}

}  // namespace polyloc::pipeline
