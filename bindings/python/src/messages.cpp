// ROS 2 messages as Python dicts. Bulk data goes through numpy (images and point clouds are
// decoded by dtype, honouring step and endianness); the rest are plain numbers and strings.
#include "messages.hpp"

#include <fmt/core.h>

namespace polyloc::py {

namespace messages_impl {  // named, not anonymous: the module is compiled in batches (unity build)

pb::module_ numpy() { return pb::module_::import("numpy"); }

Pose poseOf(const msg::Pose& p) {
  const auto& q = p.orientation;
  return Pose(Eigen::Quaterniond(q.w, q.x, q.y, q.z), {p.position.x, p.position.y, p.position.z});
}
Pose poseOf(const msg::Transform& t) {
  const auto& q = t.rotation;
  return Pose(Eigen::Quaterniond(q.w, q.x, q.y, q.z), {t.translation.x, t.translation.y, t.translation.z});
}
template <size_t N>
pb::array_t<double> square(const std::array<double, N>& a, pb::ssize_t rows) {
  pb::array_t<double> out({rows, static_cast<pb::ssize_t>(N) / rows});
  std::copy(a.begin(), a.end(), out.mutable_data());
  return out;
}
pb::array_t<double> vec3(const msg::Vector3& v) {
  pb::array_t<double> a(3);
  a.mutable_at(0) = v.x, a.mutable_at(1) = v.y, a.mutable_at(2) = v.z;
  return a;
}

pb::dict headed(const char* type, const msg::Header& h) {
  pb::dict d;
  d["type"] = type, d["stamp_ns"] = msg::toNs(h.stamp), d["frame_id"] = h.frame_id;
  return d;
}

// numpy dtype and channels of an Image encoding; empty dtype for encodings not decoded here.
std::pair<std::string, int> imageType(const std::string& e) {
  if (e == "32FC1") return {"f4", 1};
  if (e == "64FC1") return {"f8", 1};
  if (e == "16UC1" || e == "mono16") return {"u2", 1};
  if (e == "16SC1") return {"i2", 1};
  if (e == "32SC1") return {"i4", 1};
  if (e == "8UC1" || e == "mono8") return {"u1", 1};
  if (e == "rgb8" || e == "bgr8" || e == "8UC3") return {"u1", 3};
  if (e == "rgba8" || e == "bgra8" || e == "8UC4") return {"u1", 4};
  return {"", 0};
}

pb::object imageArray(const msg::Image& img) {
  const auto [code, channels] = imageType(img.encoding);
  if (code.empty()) return pb::none();
  const pb::object dtype = numpy().attr("dtype")(std::string(img.is_bigendian ? ">" : "<") + code);
  const size_t item = dtype.attr("itemsize").cast<size_t>();
  const size_t row = size_t(img.width) * channels * item;
  if (img.height == 0 || img.step < row || img.step % item || img.data.size() < size_t(img.step) * img.height)
    return pb::none();
  const pb::bytes buf(reinterpret_cast<const char*>(img.data.data()), size_t(img.step) * img.height);
  pb::object a = numpy().attr("frombuffer")(buf, dtype).attr("reshape")(img.height, img.step / item);
  a = a[pb::make_tuple(pb::slice(0, img.height, 1), pb::slice(0, img.width * channels, 1))];
  if (channels > 1) a = a.attr("reshape")(img.height, img.width, channels);
  return a.attr("astype")(numpy().attr("dtype")(code));  // native byte order, own memory
}

pb::object cloudArray(const msg::PointCloud2& c) {
  static const char* codes[] = {"", "i1", "u1", "i2", "u2", "i4", "u4", "f4", "f8"};
  pb::list names, formats, offsets;
  for (const auto& f : c.fields) {
    if (f.datatype < 1 || f.datatype > 8) return pb::none();
    names.append(f.name);
    const std::string code = std::string(c.is_bigendian ? ">" : "<") + codes[f.datatype];
    formats.append(f.count > 1 ? fmt::format("({},){}", f.count, code) : code);
    offsets.append(f.offset);
  }
  const size_t n = size_t(c.width) * c.height;
  if (c.point_step == 0 || c.data.size() < n * c.point_step || (c.height > 1 && c.row_step != c.width * c.point_step))
    return pb::none();
  pb::dict spec;
  spec["names"] = names, spec["formats"] = formats, spec["offsets"] = offsets, spec["itemsize"] = c.point_step;
  const pb::bytes buf(reinterpret_cast<const char*>(c.data.data()), n * c.point_step);
  return numpy().attr("frombuffer")(buf, numpy().attr("dtype")(spec), n).attr("copy")();
}

pb::dict convert(const msg::LaserScan& s) {
  pb::dict d = headed("sensor_msgs/msg/LaserScan", s.header);
  d["angle_min"] = s.angle_min, d["angle_max"] = s.angle_max, d["angle_increment"] = s.angle_increment;
  d["time_increment"] = s.time_increment, d["scan_time"] = s.scan_time;
  d["range_min"] = s.range_min, d["range_max"] = s.range_max;
  d["ranges"] = toArray(s.ranges), d["intensities"] = toArray(s.intensities);
  return d;
}
pb::dict convert(const msg::PointCloud2& c) {
  pb::dict d = headed("sensor_msgs/msg/PointCloud2", c.header);
  pb::list fields;
  for (const auto& f : c.fields) fields.append(f.name);
  d["height"] = c.height, d["width"] = c.width, d["fields"] = fields, d["is_dense"] = c.is_dense;
  d["points"] = cloudArray(c);  // structured (N,) array, None when the layout is not understood
  return d;
}
pb::dict convert(const msg::Image& img) {
  pb::dict d = headed("sensor_msgs/msg/Image", img.header);
  d["height"] = img.height, d["width"] = img.width, d["encoding"] = img.encoding, d["step"] = img.step;
  pb::object a = imageArray(img);
  d["image"] = a;  // (H, W) or (H, W, C); None for encodings not decoded
  if (a.is_none()) d["data"] = pb::bytes(reinterpret_cast<const char*>(img.data.data()), img.data.size());
  return d;
}
pb::dict convert(const msg::CameraInfo& c) {
  pb::dict d = headed("sensor_msgs/msg/CameraInfo", c.header);
  d["height"] = c.height, d["width"] = c.width, d["distortion_model"] = c.distortion_model;
  d["d"] = toArray(c.d), d["k"] = square(c.k, 3), d["r"] = square(c.r, 3), d["p"] = square(c.p, 3);
  return d;
}
pb::dict convert(const msg::Odometry& o) {
  pb::dict d = headed("nav_msgs/msg/Odometry", o.header);
  d["child_frame_id"] = o.child_frame_id, d["pose"] = poseOf(o.pose.pose), d["covariance"] = square(o.pose.covariance, 6);
  d["linear"] = vec3(o.twist.twist.linear), d["angular"] = vec3(o.twist.twist.angular);
  d["twist_covariance"] = square(o.twist.covariance, 6);
  return d;
}
pb::dict convert(const msg::TFMessage& tf) {
  pb::dict d;
  d["type"] = "tf2_msgs/msg/TFMessage";
  pb::list transforms;
  for (const auto& t : tf.transforms) {
    pb::dict e;
    e["stamp_ns"] = msg::toNs(t.header.stamp), e["frame_id"] = t.header.frame_id, e["child_frame_id"] = t.child_frame_id;
    e["transform"] = poseOf(t.transform);
    transforms.append(e);
  }
  d["transforms"] = transforms;
  return d;
}
pb::dict convert(const msg::PoseStamped& p) {
  pb::dict d = headed("geometry_msgs/msg/PoseStamped", p.header);
  d["pose"] = poseOf(p.pose);
  return d;
}
pb::dict convert(const msg::PoseWithCovarianceStamped& p) {
  pb::dict d = headed("geometry_msgs/msg/PoseWithCovarianceStamped", p.header);
  d["pose"] = poseOf(p.pose.pose), d["covariance"] = square(p.pose.covariance, 6);
  return d;
}
pb::dict convert(const msg::TrackArray& t) {
  pb::dict d = headed("polyloc_msgs/msg/TrackArray", t.header);
  const auto n = static_cast<pb::ssize_t>(t.tracks.size());
  pb::array_t<uint32_t> id(n);
  pb::array_t<uint8_t> status(n);
  pb::array_t<double> pos({n, pb::ssize_t{2}}), vel({n, pb::ssize_t{2}}), cov({n, pb::ssize_t{2}, pb::ssize_t{2}});
  for (pb::ssize_t i = 0; i < n; ++i) {
    const msg::Track& k = t.tracks[i];
    id.mutable_at(i) = k.id, status.mutable_at(i) = k.status;
    pos.mutable_at(i, 0) = k.x, pos.mutable_at(i, 1) = k.y, vel.mutable_at(i, 0) = k.vx, vel.mutable_at(i, 1) = k.vy;
    std::copy(k.covariance.begin(), k.covariance.end(), cov.mutable_data() + 4 * i);
  }
  d["id"] = id, d["status"] = status, d["position"] = pos, d["velocity"] = vel, d["position_cov"] = cov;
  return d;
}

}  // namespace messages_impl

pb::dict toPython(const msg::Message& m) {
  using namespace messages_impl;
  return std::visit([](const auto& v) { return convert(v); }, m);
}

}  // namespace polyloc::py
