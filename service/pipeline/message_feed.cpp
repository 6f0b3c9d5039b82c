#include "pipeline/message_feed.hpp"

#include "pipeline/shm_payloads.hpp"

#include <polyloc/io/depth_image.hpp>
#include <polyloc/io/message_pose.hpp>

#include <cstddef>
#include <cstring>

namespace polyloc::pipeline {
namespace {

int64_t stampOf(const msg::Header& h, int64_t log_ns) { return msg::toNs(h.stamp) ? msg::toNs(h.stamp) : log_ns; }

// An amplitude image, 32FC1 or 16UC1 (little-endian), into floats; false for other encodings or
// short data.
bool floats(const msg::Image& img, std::vector<float>& out) {
  const size_t n = size_t(img.width) * img.height;
  out.resize(n);
  if (img.encoding == "32FC1" && !img.is_bigendian && img.data.size() >= 4 * n && img.step == img.width * 4) {
    std::memcpy(out.data(), img.data.data(), 4 * n);
    return true;
  }
  if (img.encoding == "16UC1" && !img.is_bigendian && img.data.size() >= 2 * n && img.step == img.width * 2) {
    for (size_t k = 0; k < n; ++k) out[k] = float(uint16_t(img.data[2 * k] | img.data[2 * k + 1] << 8));
    return true;
  }
  return false;
}

}  // namespace

MessageFeed::MessageFeed(shm::Segment& seg) : seg_(seg) {
  const polyloc_shm_header& h = seg_.header();
  for (uint32_t c = 0; c < h.channel_count; ++c)
    if (h.channels[c].kind == POLYLOC_KIND_RANGES && h.channels[c].direction == POLYLOC_DIR_INPUT) scan_channels_.push_back(int(c));
}

shm::Writer& MessageFeed::writer(int ch) {
  auto& w = writers_[ch];
  if (!w) w = std::make_unique<shm::Writer>(seg_, ch);
  return *w;
}

MessageFeed::Sent MessageFeed::counted(int ch) {
  ++sent_, ++per_channel_[seg_.channel(ch).name];
  return Sent::Frame;
}

void MessageFeed::sendDepth(DepthPending& d, const std::vector<float>* amplitude) {
  const polyloc_channel_desc& c = seg_.channel(d.channel);
  shm::Writer& w = writer(d.channel);
  const size_t n = d.depth.size();
  const size_t bytes = offsetof(polyloc_depth, data) + (amplitude ? 8 : 4) * n;
  if (bytes > c.payload_max) return;  // cannot be: d.depth has the channel's size
  uint8_t* p = w.begin();
  const polyloc_depth h{d.stamp, c.width, c.height, amplitude ? 1u : 0u, 0};
  std::memcpy(p, &h, sizeof h);
  std::memcpy(p + offsetof(polyloc_depth, data), d.depth.data(), 4 * n);
  if (amplitude) std::memcpy(p + offsetof(polyloc_depth, data) + 4 * n, amplitude->data(), 4 * n);
  w.commit(uint32_t(bytes), d.stamp);
  d.pending = false;
  counted(d.channel);
}

MessageFeed::Sent MessageFeed::send(const std::string& topic, int64_t log_time_ns, const msg::Message& m, int64_t shift) {
  if (topic.rfind("/ground_truth", 0) == 0) return Sent::NotInput;
  if (const auto* o = std::get_if<msg::Odometry>(&m)) {
    const int ch = seg_.find("odom");
    if (ch < 0) return Sent::NoChannel;
    const int64_t stamp = stampOf(o->header, log_time_ns) + shift;
    polyloc_odometry p = odometryPayload(stamp, fromMsgPose(o->pose.pose));
    p.vx = o->twist.twist.linear.x, p.vy = o->twist.twist.linear.y, p.wz = o->twist.twist.angular.z;
    writer(ch).write(&p, sizeof p, stamp);
    return counted(ch);
  }
  if (const auto* s = std::get_if<msg::LaserScan>(&m)) {
    const std::string name = topic.rfind("/scan/", 0) == 0 ? topic.substr(6) : topic.substr(topic.rfind('/') + 1);
    int ch = seg_.find("scan/" + name);
    if (ch < 0 && (name == "front_laser" || name == "robot_laser") && !scan_channels_.empty()) ch = scan_channels_[0];
    if (ch < 0 && name == "rear_laser" && scan_channels_.size() > 1) ch = scan_channels_[1];
    if (ch < 0) return Sent::NoChannel;
    const size_t bytes = offsetof(polyloc_ranges, ranges) + s->ranges.size() * sizeof(float);
    if (bytes > seg_.channel(ch).payload_max) return Sent::NoChannel;  // a scan polylocd could not even hold
    const int64_t stamp = stampOf(s->header, log_time_ns) + shift;
    shm::Writer& w = writer(ch);
    uint8_t* p = w.begin();
    const polyloc_ranges h{stamp, uint32_t(s->ranges.size()), 0};
    std::memcpy(p, &h, offsetof(polyloc_ranges, ranges));
    std::memcpy(p + offsetof(polyloc_ranges, ranges), s->ranges.data(), s->ranges.size() * sizeof(float));
    w.commit(uint32_t(bytes), stamp);
    return counted(ch);
  }
  const auto* img = std::get_if<msg::Image>(&m);
  if (!img || topic.rfind("/depth/", 0) != 0) return Sent::NotInput;
  const size_t slash = topic.rfind('/');
  if (slash <= 7) return Sent::NotInput;
  const std::string cam = topic.substr(7, slash - 7), kind = topic.substr(slash + 1);
  DepthPending& d = depth_[cam];
  if (d.channel < 0) d.channel = seg_.find("depth/" + cam);
  if (d.channel < 0) return Sent::NoChannel;
  const polyloc_channel_desc& c = seg_.channel(d.channel);
  const int64_t stamp = stampOf(img->header, log_time_ns) + shift;
  if (kind == "image") {
    if (d.pending) sendDepth(d, nullptr);  // the last one never got its amplitude
    // Depth as REP-118 has it: 32FC1 metres or 16UC1 millimetres (io/depth_image.hpp).
    if (img->width != c.width || img->height != c.height || !depthImageToMetres(*img, d.depth).empty()) {
      // The header alone, so that polylocd counts and reports the bad frame.
      const polyloc_depth h{stamp, img->width, img->height, 0, 0};
      writer(d.channel).write(&h, sizeof h, stamp);
      return counted(d.channel);
    }
    d.stamp = stamp, d.pending = true;
    return Sent::Pending;
  }
  if (kind == "amplitude" && d.pending && d.stamp == stamp) {
    std::vector<float> amp;
    const bool ok = img->width == c.width && img->height == c.height && floats(*img, amp);
    sendDepth(d, ok ? &amp : nullptr);
    return Sent::Frame;
  }
  return Sent::NotInput;  // camera_info, artefacts
}

void MessageFeed::flush() {
  for (auto& [cam, d] : depth_)
    if (d.pending && d.channel >= 0) sendDepth(d, nullptr);
}

}  // namespace polyloc::pipeline
