// One message of every recorded type with non-trivial values (odd string lengths and sequence
// sizes so alignment padding shows, negative and non-integer numbers, inf), shared by the CDR
// and MCAP tests. Messages compare equal when their CDR encodings do.
#pragma once

#include <polyloc/io/cdr.hpp>

#include <cstring>
#include <limits>
#include <vector>

namespace polyloc::test {

inline std::vector<msg::Message> sampleMessages(int k = 0) {
  using namespace polyloc::msg;
  const Header h{{1700000000 + k, 123456789u + static_cast<uint32_t>(k)}, "base_link"};
  std::vector<Message> out;

  LaserScan scan{{h.stamp, "laser_front"}, -2.35f, 2.35f, 0.0087f, 1.7e-5f, 0.04f, 0.05f, 29.5f, {}, {}};
  scan.ranges = {1.25f + k, 0.5f, std::numeric_limits<float>::infinity(), 3e-3f, 29.4f};
  scan.intensities = {10.0f, 20.0f, 30.0f};
  out.push_back(scan);

  PointCloud2 pc{h, 1, 2, {}, false, 12, 24, {}, false};
  pc.fields = {{"x", 0, PointField::FLOAT32, 1}, {"y", 4, PointField::FLOAT32, 1}, {"z", 8, PointField::FLOAT32, 1}};
  const float pts[6] = {1.0f, -2.0f, 0.5f + k, 4.25f, 1e-3f, -7.0f};
  pc.data.resize(sizeof pts);
  std::memcpy(pc.data.data(), pts, sizeof pts);
  out.push_back(pc);

  Image img{{h.stamp, "tof"}, 2, 3, "32FC1", 0, 12, {}};
  for (int i = 0; i < 24; ++i) img.data.push_back(static_cast<uint8_t>(i * 11 + k));
  out.push_back(img);

  CameraInfo ci{{h.stamp, "tof"}, 50, 64, "plumb_bob", {-0.1, 0.01, 0, 0, 1e-4}, {}, {}, {}, 1, 2, {2, 3, 40, 50, true}};
  ci.k = {52.5, 0, 32, 0, 52.5, 25, 0, 0, 1};
  ci.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  ci.p = {52.5, 0, 32, 0, 0, 52.5, 25, 0, 0, 0, 1, 0};
  out.push_back(ci);

  Odometry odom{{h.stamp, "odom"}, "base_link", {}, {}};
  odom.pose.pose = {{1.5 + k, -0.25, 0.01}, {0, 0, 0.0998334166, 0.995004165}};
  odom.twist.twist = {{0.4, 0, 0}, {0, 0, -0.1}};
  for (int i = 0; i < 36; ++i) odom.pose.covariance[i] = 0.001 * i, odom.twist.covariance[i] = -0.5 * i;
  out.push_back(odom);

  TFMessage tf;
  tf.transforms = {{{h.stamp, "map"}, "odom", {{0.1, 0.2, 0}, {0, 0, 0, 1}}},
                   {{h.stamp, "odom"}, "base_link", {{1.5 + k, -0.25, 0}, {0, 0, 0.0998334166, 0.995004165}}}};
  out.push_back(tf);

  out.push_back(PoseStamped{{h.stamp, "map"}, {{1.51 + k, -0.24, 0.002}, {0.001, -0.002, 0.0998, 0.995}}});

  TrackArray tracks{{h.stamp, "map"}, {}};
  tracks.tracks.push_back({7, 1, 2.5 + k, -1.25, 0.9, -0.1, {0.01, 0.002, 0.002, 0.02}});
  tracks.tracks.push_back({9, 0, -3.0, 4.0, 0.0, 0.0, {0.25, 0, 0, 0.25}});
  out.push_back(tracks);

  PoseWithCovarianceStamped pwc{{h.stamp, "map"}, {{{1.52 + k, -0.23, 0.003}, {0, 0, 0.0998, 0.995}}, {}}};
  for (int i = 0; i < 36; ++i) pwc.pose.covariance[i] = 0.002 * i - 0.01;
  out.push_back(pwc);
  return out;
}

inline bool sameMessage(const msg::Message& a, const msg::Message& b) {
  return a.index() == b.index() && msg::encodeCdr(a) == msg::encodeCdr(b);
}

}  // namespace polyloc::test
