// Writes an MCAP file with messages of every recorded type and known, awkward values (inf and
// NaN ranges, empty and non-ASCII strings, odd sizes that need alignment padding), plus a JSON
// file with the values each message must decode to. tests/js/check_mcap.mjs reads the MCAP with
// independent libraries (@mcap/core, @foxglove/rosmsg2-serialization) and compares.
// Usage: mcap_fixture_writer OUT.mcap OUT.json [zstd|lz4|none] [chunk_size]
#include <polyloc/io/recording.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

using namespace polyloc;
using nlohmann::json;

namespace {

// JSON has no inf/NaN: they travel as strings the checker understands.
json num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}
template <class C>
json nums(const C& c) {
  json a = json::array();
  for (auto v : c) a.push_back(num(static_cast<double>(v)));
  return a;
}
json toJson(const msg::Time& t) { return {{"sec", t.sec}, {"nanosec", t.nanosec}}; }
json toJson(const msg::Header& h) { return {{"stamp", toJson(h.stamp)}, {"frame_id", h.frame_id}}; }
json toJson(const msg::Vector3& v) { return {{"x", v.x}, {"y", v.y}, {"z", v.z}}; }
json toJson(const msg::Point& v) { return {{"x", v.x}, {"y", v.y}, {"z", v.z}}; }
json toJson(const msg::Quaternion& q) { return {{"x", q.x}, {"y", q.y}, {"z", q.z}, {"w", q.w}}; }
json toJson(const msg::Pose& p) {
  return {{"position", toJson(p.position)}, {"orientation", toJson(p.orientation)}};
}
json toJson(const msg::TransformStamped& t) {
  return {{"header", toJson(t.header)},
          {"child_frame_id", t.child_frame_id},
          {"transform",
           {{"translation", toJson(t.transform.translation)}, {"rotation", toJson(t.transform.rotation)}}}};
}
json toJson(const msg::LaserScan& m) {
  return {{"header", toJson(m.header)},     {"angle_min", num(m.angle_min)},
          {"angle_max", num(m.angle_max)},  {"angle_increment", num(m.angle_increment)},
          {"time_increment", num(m.time_increment)}, {"scan_time", num(m.scan_time)},
          {"range_min", num(m.range_min)},  {"range_max", num(m.range_max)},
          {"ranges", nums(m.ranges)},       {"intensities", nums(m.intensities)}};
}
json toJson(const msg::PointCloud2& m) {
  json fields = json::array();
  for (const auto& f : m.fields)
    fields.push_back({{"name", f.name}, {"offset", f.offset}, {"datatype", f.datatype}, {"count", f.count}});
  return {{"header", toJson(m.header)}, {"height", m.height},       {"width", m.width},
          {"fields", fields},           {"is_bigendian", m.is_bigendian}, {"point_step", m.point_step},
          {"row_step", m.row_step},     {"data", nums(m.data)},     {"is_dense", m.is_dense}};
}
json toJson(const msg::Image& m) {
  return {{"header", toJson(m.header)}, {"height", m.height}, {"width", m.width},
          {"encoding", m.encoding},     {"is_bigendian", m.is_bigendian},
          {"step", m.step},             {"data", nums(m.data)}};
}
json toJson(const msg::CameraInfo& m) {
  return {{"header", toJson(m.header)},
          {"height", m.height},
          {"width", m.width},
          {"distortion_model", m.distortion_model},
          {"d", nums(m.d)},
          {"k", nums(m.k)},
          {"r", nums(m.r)},
          {"p", nums(m.p)},
          {"binning_x", m.binning_x},
          {"binning_y", m.binning_y},
          {"roi",
           {{"x_offset", m.roi.x_offset}, {"y_offset", m.roi.y_offset}, {"height", m.roi.height},
            {"width", m.roi.width}, {"do_rectify", m.roi.do_rectify}}}};
}
json toJson(const msg::Odometry& m) {
  return {{"header", toJson(m.header)},
          {"child_frame_id", m.child_frame_id},
          {"pose", {{"pose", toJson(m.pose.pose)}, {"covariance", nums(m.pose.covariance)}}},
          {"twist",
           {{"twist", {{"linear", toJson(m.twist.twist.linear)}, {"angular", toJson(m.twist.twist.angular)}}},
            {"covariance", nums(m.twist.covariance)}}}};
}
json toJson(const msg::TFMessage& m) {
  json a = json::array();
  for (const auto& t : m.transforms) a.push_back(toJson(t));
  return {{"transforms", a}};
}
json toJson(const msg::PoseStamped& m) { return {{"header", toJson(m.header)}, {"pose", toJson(m.pose)}}; }
json toJson(const msg::PoseWithCovarianceStamped& m) {
  return {{"header", toJson(m.header)}, {"pose", {{"pose", toJson(m.pose.pose)}, {"covariance", nums(m.pose.covariance)}}}};
}
// Not in the fixture (its schema is polyloc's own, not in rosmsg-msgs-common), but every type has one.
json toJson(const msg::TrackArray& m) {
  json a = json::array();
  for (const auto& t : m.tracks)
    a.push_back({{"id", t.id}, {"status", t.status}, {"x", t.x}, {"y", t.y}, {"vx", t.vx}, {"vy", t.vy}, {"covariance", t.covariance}});
  return {{"header", toJson(m.header)}, {"tracks", a}};
}

msg::Header header(int64_t t, const char* frame) { return {msg::fromNs(t), frame}; }

template <class T>
std::vector<uint8_t> bytesOf(const std::vector<T>& v) {
  std::vector<uint8_t> b(v.size() * sizeof(T));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

// Round k of messages on every topic at time t; values depend on k so rounds differ.
std::vector<std::pair<std::string, msg::Message>> round(int k, int64_t t) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<std::pair<std::string, msg::Message>> out;

  msg::LaserScan front{header(t, "laser_front"), -2.35619449f, 2.35619449f, 0.00872664626f,
                       1.7e-5f, 0.04f, 0.05f, 29.5f, {}, {}};
  front.ranges = {1.25f + k, 0.5f, inf, 3.0e-3f, 29.499f, nan, -0.0f};
  out.emplace_back("/scan_front", front);

  msg::LaserScan rear{header(t + 1000, "laser_rear"), 0, 3.14159274f, 1.5707963f, 0, 0.08f, 0.1f, 4.0f, {}, {}};
  rear.ranges = {2.0f, 2.5f - k};  // 2 ranges, 1 intensity: odd counts need padding after
  rear.intensities = {100.0f * k};
  out.emplace_back("/scan_rear", rear);

  msg::PointCloud2 pc{header(t + 2000, "lidar"), 1, 2, {}, false, 12, 24, {}, k % 2 == 0};
  pc.fields = {{"x", 0, msg::PointField::FLOAT32, 1}, {"y", 4, msg::PointField::FLOAT32, 1},
               {"z", 8, msg::PointField::FLOAT32, 1}};
  pc.data = bytesOf(std::vector<float>{1.0f, -2.0f, 0.5f + k, 4.25f, 1e-3f, -7.0f});
  out.emplace_back("/points", pc);

  msg::Image depth{header(t + 3000, "tof"), 2, 3, "32FC1", 0, 12, {}};
  depth.data = bytesOf(std::vector<float>{0.5f, 1.0f, 1.5f + k, 2.0f, 0.0f, 7.5f});
  out.emplace_back("/tof/depth", depth);

  msg::Image amp{header(t + 3000, "tof"), 1, 3, "16UC1", 0, 6, {}};
  amp.data = bytesOf(std::vector<uint16_t>{0, 65535, static_cast<uint16_t>(1000 + k)});
  out.emplace_back("/tof/amplitude", amp);

  msg::CameraInfo ci{header(t + 3000, "tof"), 50, 64, "plumb_bob", {-0.1, 0.01, 0.0, 0.0, 1e-4 * k},
                     {}, {}, {}, 1, 1, {2, 3, 40, 50, k % 2 == 1}};
  ci.k = {52.5, 0, 32.0, 0, 52.5, 25.0, 0, 0, 1};
  ci.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  ci.p = {52.5, 0, 32.0, 0, 0, 52.5, 25.0, 0, 0, 0, 1, 0};
  out.emplace_back("/tof/camera_info", ci);

  msg::Odometry odom{header(t + 4000, "odom"), "base_link", {}, {}};
  odom.pose.pose = {{1.5 * k, -0.25, 0.0}, {0, 0, 0.0998334166, 0.995004165}};
  odom.twist.twist = {{0.4, 0.0, 0.0}, {0.0, 0.0, -0.1 * k}};
  for (int i = 0; i < 36; ++i) {
    odom.pose.covariance[i] = i % 7 == 0 ? 0.01 * (i + 1) : 1e-9 * i;
    odom.twist.covariance[i] = i % 7 == 0 ? 0.002 : 0.0;
  }
  out.emplace_back("/odom", odom);

  msg::TFMessage tf;
  tf.transforms = {{header(t + 4000, "map"), "odom", {{0.1 * k, 0.2, 0}, {0, 0, 0, 1}}},
                   {header(t + 4000, "odom"), "base_link", {{1.5 * k, -0.25, 0}, {0, 0, 0.0998334166, 0.995004165}}}};
  out.emplace_back("/tf", tf);
  if (k == 0) {
    msg::TFMessage stat;
    stat.transforms = {{header(t, "base_link"), "laser_front", {{0.3, 0.2, 0.1}, {0, 0, 0.382683432, 0.923879533}}},
                       {header(t, "base_link"), "tof", {{0.35, 0, 0.6}, {0, 0.0871557427, 0, 0.996194698}}},
                       {header(t, "base_link"), "", {{0, 0, 0}, {0, 0, 0, 1}}}};
    out.emplace_back("/tf_static", stat);
  }
  out.emplace_back("/ground_truth", msg::PoseStamped{header(t + 5000, "map"),
                                                     {{1.5 * k + 0.01, -0.24, 0.002}, {0.001, -0.002, 0.0998, 0.995}}});
  msg::PoseWithCovarianceStamped amcl{header(t + 6000, "map"), {{{1.5 * k, -0.2, 0.0}, {0, 0, 0.0998, 0.995}}, {}}};
  for (int i = 0; i < 36; ++i) amcl.pose.covariance[i] = i % 7 == 0 ? 0.02 * (i + 1) : -1e-6 * i;
  out.emplace_back("/pose", amcl);  // what the live view sends (docs/live.md)
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s OUT.mcap OUT.json [zstd|lz4|none] [chunk_size]\n", argv[0]);
    return 2;
  }
  McapWriteOptions opt;
  if (argc > 3) opt.compression = std::string(argv[3]) == "none" ? "" : argv[3];
  opt.chunk_size = argc > 4 ? std::stoull(argv[4]) : 1024;  // small: several chunks
  try {
    auto writer = createMcap(argv[1], opt);
    json expected = {{"compression", opt.compression}, {"messages", json::array()}};
    const int64_t t0 = 1700000000123456789;  // ns; beyond 2^53, so times travel as strings
    for (int k = 0; k < 4; ++k) {
      int64_t t = t0 + int64_t{k} * 100000000;
      for (auto& [topic, m] : round(k, t)) {
        int64_t log_time = msg::toNs(std::visit(
            [](const auto& v) {
              if constexpr (requires { v.header; }) return v.header.stamp;
              else return v.transforms.front().header.stamp;
            },
            m));
        writer->write(topic, log_time, m);
        expected["messages"].push_back({{"topic", topic},
                                        {"type", msg::typeName(m)},
                                        {"log_time", std::to_string(log_time)},
                                        {"message", std::visit([](const auto& v) { return toJson(v); }, m)}});
      }
    }
    writer->close();
    std::ofstream(argv[2]) << expected.dump(1) << "\n";
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcap_fixture_writer: %s\n", e.what());
    return 1;
  }
  return 0;
}
