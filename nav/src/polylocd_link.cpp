#include <polynav/polylocd_link.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace polynav {

std::optional<VrsFrame> decodeVrs(const void* slot, size_t size, std::string* why) {
  constexpr size_t head = offsetof(polyloc_vrs, ranges);
  polyloc_vrs v{};
  if (!slot || size < head) {
    if (why) *why = "VRS frame of " + std::to_string(size) + " bytes, shorter than its " + std::to_string(head) + "-byte header";
    return std::nullopt;
  }
  std::memcpy(&v, slot, head);
  if (v.count > (size - head) / sizeof(float)) {
    if (why) *why = "VRS frame of " + std::to_string(size) + " bytes claims " + std::to_string(v.count) + " ranges";
    return std::nullopt;
  }
  VrsFrame f;
  f.stamp_ns = v.stamp_ns;
  f.scan.angle_min = v.angle_min + v.angle_increment / 2;  // segment centres
  f.scan.angle_increment = v.angle_increment;
  f.scan.range_max = v.range_max;
  f.scan.ranges.resize(v.count);
  if (v.count > 0)  // an empty vector's data() may be null, which memcpy must not get
    std::memcpy(f.scan.ranges.data(), static_cast<const char*>(slot) + head, v.count * sizeof(float));
  return f;
}

double secondsBetween(int64_t t0_ns, int64_t t_ns) {
  return double(static_cast<__int128>(t_ns) - t0_ns) * 1e-9;
}

int64_t stopStamp(int64_t last_ns, int64_t now_ns) {
  if (last_ns <= 0) return now_ns;
  return last_ns == std::numeric_limits<int64_t>::max() ? last_ns : last_ns + 1;
}

Eigen::Vector3d poseNow(const polyloc_pose& p, const polyloc_odometry* odom) {
  if (!odom) return {p.x, p.y, polyloc_quaternion_yaw(p.qw, p.qx, p.qy, p.qz)};
  const double myaw = polyloc_quaternion_yaw(p.map_odom[3], p.map_odom[4], p.map_odom[5], p.map_odom[6]);
  const double oyaw = polyloc_quaternion_yaw(odom->qw, odom->qx, odom->qy, odom->qz);
  const double c = std::cos(myaw), s = std::sin(myaw);
  return {p.map_odom[0] + c * odom->x - s * odom->y, p.map_odom[1] + s * odom->x + c * odom->y,
          std::remainder(myaw + oyaw, 2 * M_PI)};
}

PoseRead readPoseNow(polyloc_client* c, int odom_ch) {
  polyloc_pose p{};  // a failed read leaves the identity, never uninitialised memory
  p.qw = 1, p.map_odom[3] = 1;
  PoseRead r;
  if (polyloc_read_pose(c, &p, nullptr) != POLYLOC_OK) {
    p = polyloc_pose{};  // a read that failed half-way may have written part of it
    p.qw = 1, p.map_odom[3] = 1;
  } else {
    r.localised = p.status == POLYLOC_POSE_TRACKING;
  }
  polyloc_odometry odom{};
  polyloc_frame_info info{};
  const bool have_odom = odom_ch >= 0 && polyloc_read_newest(c, odom_ch, &odom, sizeof odom, &info) == POLYLOC_OK &&
                         info.size >= sizeof odom;  // a short frame is not odometry
  r.pose = poseNow(p, have_odom ? &odom : nullptr);
  return r;
}

}  // namespace polynav
