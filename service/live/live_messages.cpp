#include "live/live_messages.hpp"

#include <polyloc/io/cdr.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/map/slice.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace polyloc::live {
namespace {

using json = nlohmann::json;

Bytes toBytes(const json& j) {
  const std::string s = j.dump();
  return Bytes(s.begin(), s.end());
}
// Millimetres are enough for a view and keep the JSON small ("1.2", not "1.2000000476837158").
double mm(double v) { return std::round(v * 1000.0) / 1000.0; }

msg::Header header(int64_t stamp_ns, const std::string& frame) { return {msg::fromNs(stamp_ns), frame}; }

json foxgloveTime(int64_t ns) { return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}}; }

// Colours in the 3D view (dark background): walls light, then as the PNGs' label colours.
json sceneColor(const std::string& label) {
  auto rgba = [](double r, double g, double b, double a) { return json{{"r", r}, {"g", g}, {"b", b}, {"a", a}}; };
  if (label == "glass") return rgba(0.0, 0.67, 0.78, 0.35);
  if (label == "door") return rgba(0.59, 0.35, 0.16, 0.9);
  if (label == "danger") return rgba(0.86, 0.12, 0.12, 0.8);
  if (label == "ramp") return rgba(0.94, 0.55, 0.08, 0.9);
  if (label == "floor") return rgba(0.35, 0.35, 0.35, 1.0);
  if (label == "wall" || label.empty()) return rgba(0.8, 0.8, 0.8, 1.0);
  return rgba(0.35, 0.45, 0.7, 1.0);  // furniture and other objects
}

// Compact JSON Schemas: Foxglove picks its panels by schema name; the schema documents the fields.
const char* jsonSchema(const std::string& name) {
  if (name == "foxglove.SceneUpdate")
    return R"({"title":"foxglove.SceneUpdate","type":"object","properties":{"deletions":{"type":"array"},"entities":{"type":"array","items":{"type":"object","properties":{"timestamp":{"type":"object"},"frame_id":{"type":"string"},"id":{"type":"string"},"lifetime":{"type":"object"},"frame_locked":{"type":"boolean"},"triangles":{"type":"array"}}}}}})";
  if (name == "polyloc.MapSlice")
    return R"({"title":"polyloc.MapSlice","type":"object","properties":{"frame_id":{"type":"string"},"height":{"type":"number"},"bounds":{"type":"array","items":{"type":"number"}},"labels":{"type":"array","items":{"type":"string"}},"segments":{"type":"array","items":{"type":"number"}},"segment_label":{"type":"array","items":{"type":"integer"}}}})";
  if (name == "polyloc.TopView")
    return R"({"title":"polyloc.TopView","type":"object","properties":{"stamp_ns":{"type":"integer"},"frame_id":{"type":"string"},"pose":{"type":["object","null"]},"particles":{"type":"array","items":{"type":"number"}},"vrs":{"type":"array","items":{"type":"number"}},"tracks":{"type":"array"},"status":{"type":"string"}}})";
  if (name == "polyloc.Health")
    return R"({"title":"polyloc.Health","type":"object","properties":{"stamp_ns":{"type":"integer"},"cycles":{"type":"integer"},"poses":{"type":"integer"},"flags":{"type":"integer"},"inputs":{"type":"array"},"viewers":{"type":"object"}}})";
  throw std::logic_error("live: no JSON schema named " + name);
}

msg::PointField field(const char* name, uint32_t offset) { return {name, offset, msg::PointField::FLOAT32, 1}; }

Bytes cloud(int64_t stamp_ns, const std::string& frame, std::vector<msg::PointField> fields, std::vector<float> values) {
  msg::PointCloud2 c;
  c.header = header(stamp_ns, frame);
  c.point_step = uint32_t(4 * fields.size());
  c.fields = std::move(fields);
  c.width = uint32_t(values.size() / (c.point_step / 4));
  c.row_step = c.point_step * c.width;
  c.data.resize(values.size() * 4);
  if (!values.empty()) std::memcpy(c.data.data(), values.data(), c.data.size());
  return msg::encodeCdr(c);
}

}  // namespace

ChannelSpec cdrChannel(const std::string& topic, const std::string& type, bool latched) {
  return {topic, "cdr", type, msg::ros2msgSchema(type), "ros2msg", latched};
}

ChannelSpec jsonChannel(const std::string& topic, const std::string& schema_name, bool latched) {
  return {topic, "json", schema_name, jsonSchema(schema_name), "jsonschema", latched};
}

Bytes sceneOfMesh(const Mesh& map) {
  std::map<std::string, json> lists;  // label class -> points
  for (size_t t = 0; t < map.numTriangles(); ++t) {
    json& pts = lists[normalizeLabel(map.labelOf(t))];
    if (pts.is_null()) pts = json::array();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f& v = map.vertices[map.triangles[t][k]];
      pts.push_back({{"x", mm(v.x())}, {"y", mm(v.y())}, {"z", mm(v.z())}});
    }
  }
  json triangles = json::array();
  const json identity{{"position", {{"x", 0}, {"y", 0}, {"z", 0}}}, {"orientation", {{"x", 0}, {"y", 0}, {"z", 0}, {"w", 1}}}};
  for (auto& [label, pts] : lists)
    triangles.push_back({{"pose", identity}, {"points", std::move(pts)}, {"color", sceneColor(label)}, {"colors", json::array()},
                         {"indices", json::array()}});
  json entity{{"timestamp", foxgloveTime(0)}, {"frame_id", "map"},       {"id", "map"},
              {"lifetime", foxgloveTime(0)},  {"frame_locked", true},     {"metadata", json::array()},
              {"arrows", json::array()},      {"cubes", json::array()},   {"spheres", json::array()},
              {"cylinders", json::array()},   {"lines", json::array()},   {"triangles", std::move(triangles)},
              {"texts", json::array()},       {"models", json::array()}};
  return toBytes(json{{"deletions", json::array()}, {"entities", json::array({std::move(entity)})}});
}

Bytes mapSliceJson(const Mesh& map, float height) {
  const auto segs = sliceMesh(map, height);
  json xy = json::array(), label = json::array(), names = json::array();
  std::map<std::string, int> ids;
  Eigen::AlignedBox2f box;
  for (const SliceSegment& s : segs) {
    const std::string name = normalizeLabel(map.label_names[s.label]);
    auto [it, fresh] = ids.emplace(name, int(ids.size()));
    if (fresh) names.push_back(name);
    for (const Eigen::Vector2f& p : {s.a, s.b}) xy.push_back(mm(p.x())), xy.push_back(mm(p.y())), box.extend(p);
    label.push_back(it->second);
  }
  if (box.isEmpty()) box = Eigen::AlignedBox2f(map.bounds().min().head<2>(), map.bounds().max().head<2>());
  return toBytes(json{{"frame_id", "map"},
                      {"height", height},
                      {"bounds", {mm(box.min().x()), mm(box.min().y()), mm(box.max().x()), mm(box.max().y())}},
                      {"labels", names},
                      {"segments", xy},
                      {"segment_label", label}});
}

Bytes poseCdr(const MclEstimate& e) {
  msg::PoseWithCovarianceStamped m;
  m.header = header(e.stamp_ns, "map");
  m.pose.pose = toMsgPose(e.pose);
  // polyloc's order (x y z roll pitch yaw) is ROS's (x y z rotX rotY rotZ): row-major as is.
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) m.pose.covariance[size_t(6 * r + c)] = e.covariance(r, c);
  return msg::encodeCdr(m);
}

Bytes groundTruthCdr(int64_t stamp_ns, const Pose& map_T_base) {
  return msg::encodeCdr(msg::PoseStamped{header(stamp_ns, "map"), toMsgPose(map_T_base)});
}

size_t particleStride(size_t n, size_t max_points) {
  const size_t m = std::max<size_t>(1, max_points);
  return std::max<size_t>(1, (n + m - 1) / m);
}

Bytes particlesCdr(int64_t stamp_ns, const ParticleSet& p, size_t max_points) {
  const size_t n = p.size(), step = particleStride(n, max_points);
  const double top = n ? *std::max_element(p.logw.begin(), p.logw.end()) : 0.0;
  std::vector<float> v;
  v.reserve(5 * (n / step + 1));
  for (size_t i = 0; i < n; i += step) {
    const Pose q = p.pose(i);
    const double w = std::isfinite(p.logw[i]) ? std::exp(p.logw[i] - top) : 0.0;
    v.insert(v.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.yaw()), float(w)});
  }
  return cloud(stamp_ns, "map", {field("x", 0), field("y", 4), field("z", 8), field("yaw", 12), field("weight", 16)}, std::move(v));
}

Bytes tfCdr(int64_t stamp_ns, const Pose& map_T_odom, const Pose& odom_T_base) {
  msg::TFMessage m;
  m.transforms.push_back({header(stamp_ns, "map"), "odom", toMsgTransform(map_T_odom)});
  m.transforms.push_back({header(stamp_ns, "odom"), "base_link", toMsgTransform(odom_T_base)});
  return msg::encodeCdr(m);
}

Bytes tfStaticCdr(const Rig& rig) {
  msg::TFMessage m;
  for (const Sensor& s : rig.sensors) m.transforms.push_back({header(0, "base_link"), s.name, toMsgTransform(s.mount)});
  return msg::encodeCdr(m);
}

Bytes laserScanCdr(int64_t stamp_ns, const std::string& frame, const ScanShape& shape, std::span<const float> ranges) {
  msg::LaserScan s;
  s.header = header(stamp_ns, frame);
  s.angle_min = shape.angle_min, s.angle_increment = shape.angle_increment;
  s.angle_max = shape.angle_min + shape.angle_increment * float(ranges.empty() ? 0 : ranges.size() - 1);
  s.range_min = shape.range_min, s.range_max = shape.range_max;
  s.ranges.assign(ranges.begin(), ranges.end());
  return msg::encodeCdr(s);
}

Bytes vrsCdr(const VirtualScan& v) {
  return laserScanCdr(v.stamp_ns, "base_link", {v.angleOf(0), v.angle_increment, v.range_min, v.range_max}, v.ranges);
}

Bytes tracksCdr(const polyloc_tracks& t) {
  msg::TrackArray m;
  m.header = header(t.stamp_ns, "map");
  for (uint32_t i = 0; i < t.count && i < POLYLOC_MAX_TRACKS; ++i) {
    const polyloc_track& k = t.tracks[i];
    msg::Track o{k.id, uint8_t(k.status), k.x, k.y, k.vx, k.vy, {}};
    std::copy(k.covariance, k.covariance + 4, o.covariance.begin());
    m.tracks.push_back(o);
  }
  return msg::encodeCdr(m);
}

Bytes depthCdr(int64_t stamp_ns, const DepthFilterResult& d) {
  std::vector<float> v;
  v.reserve(3 * d.x.size());
  for (size_t i = 0; i < d.x.size(); ++i) v.insert(v.end(), {d.x[i], d.y[i], d.z[i]});
  return cloud(stamp_ns, "base_link", {field("x", 0), field("y", 4), field("z", 8)}, std::move(v));
}

Bytes rangesCloudCdr(int64_t stamp_ns, const std::string& frame, const BeamSet& beams, std::span<const float> ranges) {
  std::vector<float> v;
  v.reserve(3 * ranges.size());
  for (size_t i = 0; i < ranges.size() && i < beams.size(); ++i) {
    const float r = ranges[i];
    if (!(r >= beams.range_min && r <= beams.range_max)) continue;  // NaN, no return, out of range
    v.insert(v.end(), {r * beams.dx[i], r * beams.dy[i], r * beams.dz[i]});
  }
  return cloud(stamp_ns, frame, {field("x", 0), field("y", 4), field("z", 8)}, std::move(v));
}

Bytes topViewJson(const TopView& v) {
  json pose = nullptr;
  if (v.have_pose) {
    const auto& c = v.pose.covariance;
    pose = {{"x", mm(v.pose.pose.x())}, {"y", mm(v.pose.pose.y())}, {"yaw", std::round(v.pose.pose.yaw() * 1e4) / 1e4},
            {"cov_xx", c(0, 0)}, {"cov_xy", c(0, 1)}, {"cov_yy", c(1, 1)}};
  }
  json particles = json::array(), vrs = json::array(), tracks = json::array();
  for (size_t i = 0; i < v.particles.size(); ++i) particles.push_back(i % 3 == 2 ? std::round(v.particles[i] * 1e3) / 1e3 : mm(v.particles[i]));
  for (float f : v.vrs) vrs.push_back(mm(f));
  for (const polyloc_track& t : v.tracks)
    tracks.push_back({{"id", t.id}, {"x", mm(t.x)}, {"y", mm(t.y)}, {"vx", mm(t.vx)}, {"vy", mm(t.vy)}, {"confirmed", t.status == 1}});
  return toBytes(json{{"stamp_ns", v.stamp_ns}, {"frame_id", "map"}, {"pose", pose}, {"particles", particles},
                      {"vrs", vrs},             {"tracks", tracks},     {"status", v.status}});
}

Bytes healthJson(const polyloc_health& h, const std::vector<std::string>& inputs, const ServerStats& s) {
  json in = json::array();
  for (uint32_t i = 0; i < h.inputs && i < POLYLOC_MAX_INPUTS; ++i) {
    const polyloc_input_health& x = h.input[i];
    in.push_back({{"name", i < inputs.size() ? inputs[i] : std::to_string(i)},
                  {"taken", x.taken},
                  {"rejected_nan", x.rejected_nan},
                  {"rejected_size", x.rejected_size},
                  {"rejected_stale", x.rejected_stale},
                  {"rejected_future", x.rejected_future},
                  {"overruns", x.overruns},
                  {"last_stamp_ns", x.last_stamp_ns},
                  {"silent", x.silent != 0},
                  {"map_fit_permille", x.map_fit_permille},
                  {"extrapolated", x.extrapolated}});
  }
  json viewers{{"clients", s.clients},           {"connections", s.connections},
               {"refused", s.refused},           {"messages_sent", s.messages_sent},
               {"messages_dropped", s.messages_dropped}, {"disconnected_slow", s.disconnected_slow},
               {"bad_messages", s.bad_messages}, {"http_requests", s.http_requests},
               {"refused_pending", s.refused_pending}, {"rate_limited", s.rate_limited},
               {"accept_errors", s.accept_errors}};
  return toBytes(json{{"stamp_ns", h.stamp_ns},         {"cycles", h.cycles},   {"poses", h.poses},
                      {"vrs", h.vrs},                   {"tracks", h.tracks},   {"cycle_p50_ms", h.cycle_p50_ms},
                      {"cycle_p99_ms", h.cycle_p99_ms}, {"flags", h.flags},     {"inputs", in},
                      {"viewers", viewers}});
}

}  // namespace polyloc::live
