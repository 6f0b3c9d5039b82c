// The ROS 2 messages of one simulated sensor frame (see sensor_sim.hpp and simulator.hpp).
#include "sensor_sim.hpp"

#include <polyloc/io/message_pose.hpp>
#include <polyloc/geometry/random.hpp>

#include <cmath>
#include <cstring>

namespace polyloc {

namespace detail {

namespace {

// REP-103 optical frame (z forward, x right, y down) in the body frame (x forward, y left, z up).
const Pose kBodyToOptical = Pose::fromXYZRPY(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);

void putFloats(std::vector<uint8_t>& data, const std::vector<float>& v) {
  data.resize(v.size() * sizeof(float));
  std::memcpy(data.data(), v.data(), data.size());  // little-endian hosts only (is_bigendian = 0)
}

msg::Image floatImage(const msg::Header& h, int w, int hgt, const std::vector<float>& v) {
  msg::Image img;
  img.header = h;
  img.width = static_cast<uint32_t>(w), img.height = static_cast<uint32_t>(hgt);
  img.encoding = "32FC1";
  img.is_bigendian = 0;
  img.step = static_cast<uint32_t>(w) * 4;
  putFloats(img.data, v);
  return img;
}

}  // namespace

void SensorSim::staticTransforms(const std::string& base_frame, int64_t stamp,
                                 std::vector<msg::TransformStamped>& out) const {
  msg::TransformStamped t;
  t.header.stamp = msg::fromNs(stamp);
  t.header.frame_id = base_frame;
  t.child_frame_id = sensor_.name;
  t.transform = toMsgTransform(sensor_.mount);
  out.push_back(t);
  if (!depth_factor_.empty()) {
    t.header.frame_id = sensor_.name;
    t.child_frame_id = optical_frame_;
    t.transform = toMsgTransform(kBodyToOptical);
    out.push_back(t);
  }
}

void SensorSim::buildMessages(FrameJob& job) const {
  const SimFrame& f = job.frame;
  const int order = 10 + static_cast<int>(index_);
  msg::Header header;
  header.stamp = msg::fromNs(f.stamp_ns);
  header.frame_id = sensor_.name;

  if (const auto* p = std::get_if<PlanarScannerSpec>(&sensor_.spec)) {
    msg::LaserScan scan;
    scan.header = header;
    scan.angle_min = static_cast<float>(p->angleMin());
    scan.angle_increment = static_cast<float>(p->resolution_rad);
    scan.angle_max = static_cast<float>(p->angleMin() + (beams_.size() - 1) * p->resolution_rad);
    scan.time_increment = 0.f;  // the whole scan at the stamp: no motion within a scan
    scan.scan_time = static_cast<float>(1.0 / p->rate_hz);
    scan.range_min = static_cast<float>(p->range_min);
    scan.range_max = static_cast<float>(p->range_max);
    scan.ranges = f.measured;
    job.messages.push_back({f.stamp_ns, order, "/scan/" + sensor_.name, std::move(scan)});
    return;
  }

  if (const auto* l = std::get_if<LidarSpec>(&sensor_.spec)) {
    msg::PointCloud2 pc;
    pc.header = header;
    pc.fields = {{"x", 0, msg::PointField::FLOAT32, 1},
                 {"y", 4, msg::PointField::FLOAT32, 1},
                 {"z", 8, msg::PointField::FLOAT32, 1},
                 {"intensity", 12, msg::PointField::FLOAT32, 1},
                 {"ring", 16, msg::PointField::UINT16, 1}};
    pc.point_step = 20;  // 2 bytes of padding keep points 4-byte aligned
    const size_t na = l->numAzimuths();
    for (size_t b = 0; b < beams_.size(); ++b) {
      const float r = f.measured[b];
      if (!std::isfinite(r)) continue;
      const float pt[4] = {r * beams_.dx[b], r * beams_.dy[b], r * beams_.dz[b],
                           100.f * reflectivity_[std::min<size_t>(f.label[b], reflectivity_.size() - 1)]};
      const uint16_t ring = static_cast<uint16_t>(b / na);
      const size_t at = pc.data.size();
      pc.data.resize(at + pc.point_step, 0);
      std::memcpy(pc.data.data() + at, pt, sizeof(pt));
      std::memcpy(pc.data.data() + at + 16, &ring, sizeof(ring));
    }
    pc.width = static_cast<uint32_t>(pc.data.size() / pc.point_step);
    pc.height = 1;
    pc.row_step = static_cast<uint32_t>(pc.data.size());
    pc.is_dense = true;
    job.messages.push_back({f.stamp_ns, order, "/points/" + sensor_.name, std::move(pc)});
    return;
  }

  const auto& cam = std::get<DepthCameraSpec>(sensor_.spec);
  header.frame_id = optical_frame_;
  const size_t n = beams_.size();
  std::vector<float> depth(n), amplitude(n, 0.f);
  const CounterRng rng(opt_.seed);
  const uint64_t stream = frameStream(index_, f.index);
  for (size_t b = 0; b < n; ++b) {
    const float r = f.measured[b];
    depth[b] = std::isfinite(r) ? r * depth_factor_[b] : std::numeric_limits<float>::quiet_NaN();
    const float re = f.exact[b];
    if (std::isfinite(re)) {
      const float rr = std::max(re, 0.05f);
      double a = noise_.amplitude_scale * reflectivity_[std::min<size_t>(f.label[b], reflectivity_.size() - 1)] *
                 job.cos_incidence[b] / (rr * rr);
      if (opt_.noise_enabled) a *= 1.0 + noise_.amplitude_noise * rng.normal(stream, b, 1);  // draw k = 1: uniforms 2, 3
      amplitude[b] = static_cast<float>(std::max(0.0, a));
    }
  }
  const std::string base = "/depth/" + sensor_.name;
  job.messages.push_back({f.stamp_ns, order, base + "/image", floatImage(header, cam.width, cam.height, depth)});
  job.messages.push_back({f.stamp_ns, order, base + "/amplitude", floatImage(header, cam.width, cam.height, amplitude)});
  msg::CameraInfo info;
  info.header = header;
  info.width = static_cast<uint32_t>(cam.width), info.height = static_cast<uint32_t>(cam.height);
  info.distortion_model = "plumb_bob";
  info.d = {0, 0, 0, 0, 0};
  // DepthCameraSpec puts pixel centres at u + 0.5; ROS at integer u: the principal point moves by 0.5.
  const double cx = cam.cx() - 0.5, cy = cam.cy() - 0.5;
  info.k = {cam.fx(), 0, cx, 0, cam.fy(), cy, 0, 0, 1};
  info.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.p = {cam.fx(), 0, cx, 0, 0, cam.fy(), cy, 0, 0, 0, 1, 0};
  job.messages.push_back({f.stamp_ns, order, base + "/camera_info", std::move(info)});
}

}  // namespace detail
}  // namespace polyloc
