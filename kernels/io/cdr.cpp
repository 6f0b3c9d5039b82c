// CDR codec of the recorded message types via Fast-CDR (1.0 API), laid out as rmw_fastrtps
// does: DDS_CDR encapsulation (00 01 00 00 for little endian), alignment counted from after the
// 4-byte header, strings as uint32 length (with the NUL) + bytes + NUL, sequences as uint32
// count + elements, fixed arrays without count. Decoding never trusts a length: a count is
// checked against the bytes left before anything is allocated.
#include <polyloc/io/cdr.hpp>

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>
#include <fastcdr/exceptions/NotEnoughMemoryException.h>

#include <cstring>

namespace polyloc::msg {
namespace {

namespace fc = eprosima::fastcdr;

// ---- encoding ---------------------------------------------------------------------------

void put(fc::Cdr& c, const Time& t) { c << t.sec << t.nanosec; }
void put(fc::Cdr& c, const Header& h) {
  put(c, h.stamp);
  c << h.frame_id;
}
void put(fc::Cdr& c, const Vector3& v) { c << v.x << v.y << v.z; }
void put(fc::Cdr& c, const Point& p) { c << p.x << p.y << p.z; }
void put(fc::Cdr& c, const Quaternion& q) { c << q.x << q.y << q.z << q.w; }
void put(fc::Cdr& c, const Pose& p) {
  put(c, p.position);
  put(c, p.orientation);
}
template <class T, size_t N>
void put(fc::Cdr& c, const std::array<T, N>& a) {
  c.serializeArray(a.data(), N);
}
template <class T>
void putSeq(fc::Cdr& c, const std::vector<T>& v) {
  c << static_cast<uint32_t>(v.size());
  c.serializeArray(v.data(), v.size());  // aligns only when there is at least one element
}
void put(fc::Cdr& c, const Transform& t) {
  put(c, t.translation);
  put(c, t.rotation);
}
void put(fc::Cdr& c, const TransformStamped& t) {
  put(c, t.header);
  c << t.child_frame_id;
  put(c, t.transform);
}
void put(fc::Cdr& c, const PoseStamped& m) {
  put(c, m.header);
  put(c, m.pose);
}
void put(fc::Cdr& c, const TrackArray& m) {
  put(c, m.header);
  c << static_cast<uint32_t>(m.tracks.size());
  for (const Track& t : m.tracks) {
    c << t.id << t.status << t.x << t.y << t.vx << t.vy;
    for (double v : t.covariance) c << v;
  }
}
void put(fc::Cdr& c, const LaserScan& m) {
  put(c, m.header);
  c << m.angle_min << m.angle_max << m.angle_increment << m.time_increment << m.scan_time
    << m.range_min << m.range_max;
  putSeq(c, m.ranges);
  putSeq(c, m.intensities);
}
void put(fc::Cdr& c, const PointCloud2& m) {
  put(c, m.header);
  c << m.height << m.width << static_cast<uint32_t>(m.fields.size());
  for (const PointField& f : m.fields) c << f.name << f.offset << f.datatype << f.count;
  c << m.is_bigendian << m.point_step << m.row_step;
  putSeq(c, m.data);
  c << m.is_dense;
}
void put(fc::Cdr& c, const Image& m) {
  put(c, m.header);
  c << m.height << m.width << m.encoding << m.is_bigendian << m.step;
  putSeq(c, m.data);
}
void put(fc::Cdr& c, const CameraInfo& m) {
  put(c, m.header);
  c << m.height << m.width << m.distortion_model;
  putSeq(c, m.d);
  put(c, m.k);
  put(c, m.r);
  put(c, m.p);
  c << m.binning_x << m.binning_y;
  c << m.roi.x_offset << m.roi.y_offset << m.roi.height << m.roi.width << m.roi.do_rectify;
}
void put(fc::Cdr& c, const Odometry& m) {
  put(c, m.header);
  c << m.child_frame_id;
  put(c, m.pose.pose);
  put(c, m.pose.covariance);
  put(c, m.twist.twist.linear);
  put(c, m.twist.twist.angular);
  put(c, m.twist.covariance);
}
void put(fc::Cdr& c, const PoseWithCovarianceStamped& m) {
  put(c, m.header);
  put(c, m.pose.pose);
  put(c, m.pose.covariance);
}
void put(fc::Cdr& c, const TFMessage& m) {
  c << static_cast<uint32_t>(m.transforms.size());
  for (const TransformStamped& t : m.transforms) put(c, t);
}

// Upper bound of the encoded size, so the buffer is allocated once (Fast-CDR's own growth
// would copy a large image several times).
size_t sizeHint(const Message& m) {
  return 512 + std::visit(
                   [](const auto& v) -> size_t {
                     using T = std::decay_t<decltype(v)>;
                     if constexpr (std::is_same_v<T, LaserScan>)
                       return 4 * (v.ranges.size() + v.intensities.size()) + v.header.frame_id.size();
                     else if constexpr (std::is_same_v<T, PointCloud2>) {
                       size_t n = v.data.size() + v.header.frame_id.size();
                       for (const auto& f : v.fields) n += 24 + f.name.size();
                       return n;
                     } else if constexpr (std::is_same_v<T, Image>)
                       return v.data.size() + v.encoding.size() + v.header.frame_id.size();
                     else if constexpr (std::is_same_v<T, CameraInfo>)
                       return 8 * v.d.size() + 300 + v.distortion_model.size() + v.header.frame_id.size();
                     else if constexpr (std::is_same_v<T, PoseWithCovarianceStamped>)
                       return 350 + v.header.frame_id.size();
                     else if constexpr (std::is_same_v<T, Odometry>)
                       return 700 + v.child_frame_id.size() + v.header.frame_id.size();
                     else if constexpr (std::is_same_v<T, TrackArray>)
                       return 80 * v.tracks.size() + v.header.frame_id.size() + 80;
                     else if constexpr (std::is_same_v<T, TFMessage>) {
                       size_t n = 0;
                       for (const auto& t : v.transforms)
                         n += 100 + t.header.frame_id.size() + t.child_frame_id.size();
                       return n;
                     } else
                       return 80 + v.header.frame_id.size();
                   },
                   m);
}

// ---- decoding ---------------------------------------------------------------------------

// Fast-CDR deserializer that knows how many bytes are left and which field it is on, so errors
// can say where a message went wrong.
struct Reader {
  fc::Cdr& c;
  size_t size;
  const char* field = "encapsulation";

  size_t left() const {
    size_t used = c.getSerializedDataLength();
    return used < size ? size - used : 0;
  }
  // A sequence count, rejected when even the smallest elements could not fit in what is left.
  uint32_t count(const char* what, size_t min_element_bytes) {
    field = what;
    uint32_t n = 0;
    c >> n;
    if (min_element_bytes > 0 && uint64_t{n} * min_element_bytes > left())
      throw IoError("sequence " + std::string(what) + " claims " + std::to_string(n) +
                    " elements but only " + std::to_string(left()) + " bytes are left");
    return n;
  }
  template <class T>
  void seq(const char* what, std::vector<T>& v) {
    uint32_t n = count(what, sizeof(T));
    v.resize(n);
    if (n) c.deserializeArray(v.data(), n);
  }
  template <class T>
  Reader& operator()(const char* what, T& v) {
    field = what;
    c >> v;
    return *this;
  }
  template <class T, size_t N>
  void array(const char* what, std::array<T, N>& a) {
    field = what;
    c.deserializeArray(a.data(), N);
  }
};

void get(Reader& r, Header& h) {
  r("header.stamp.sec", h.stamp.sec)("header.stamp.nanosec", h.stamp.nanosec);
  r("header.frame_id", h.frame_id);
}
void get(Reader& r, Vector3& v) { r("x", v.x)("y", v.y)("z", v.z); }
void get(Reader& r, Point& p) { r("x", p.x)("y", p.y)("z", p.z); }
void get(Reader& r, Quaternion& q) { r("x", q.x)("y", q.y)("z", q.z)("w", q.w); }
void get(Reader& r, Pose& p) {
  get(r, p.position);
  get(r, p.orientation);
}
void get(Reader& r, TransformStamped& t) {
  get(r, t.header);
  r("child_frame_id", t.child_frame_id);
  get(r, t.transform.translation);
  get(r, t.transform.rotation);
}
void get(Reader& r, PoseStamped& m) {
  get(r, m.header);
  get(r, m.pose);
}
void get(Reader& r, TrackArray& m) {
  get(r, m.header);
  // id 4 + status 1 (+3 padding) + 4 x 8 + 4 x 8: the least a Track takes
  const uint32_t n = r.count("tracks", 72);
  m.tracks.resize(n);
  for (Track& t : m.tracks) {
    r("tracks.id", t.id)("tracks.status", t.status)("tracks.x", t.x)("tracks.y", t.y)("tracks.vx", t.vx)("tracks.vy", t.vy);
    r.array("tracks.covariance", t.covariance);
  }
}
void get(Reader& r, LaserScan& m) {
  get(r, m.header);
  r("angle_min", m.angle_min)("angle_max", m.angle_max)("angle_increment", m.angle_increment);
  r("time_increment", m.time_increment)("scan_time", m.scan_time);
  r("range_min", m.range_min)("range_max", m.range_max);
  r.seq("ranges", m.ranges);
  r.seq("intensities", m.intensities);
}
void get(Reader& r, PointCloud2& m) {
  get(r, m.header);
  r("height", m.height)("width", m.width);
  uint32_t n = r.count("fields", 13);  // empty name (4) + offset (4) + datatype (1) + count (4)
  m.fields.resize(n);
  for (PointField& f : m.fields)
    r("fields.name", f.name)("fields.offset", f.offset)("fields.datatype", f.datatype)(
        "fields.count", f.count);
  r("is_bigendian", m.is_bigendian)("point_step", m.point_step)("row_step", m.row_step);
  r.seq("data", m.data);
  r("is_dense", m.is_dense);
}
void get(Reader& r, Image& m) {
  get(r, m.header);
  r("height", m.height)("width", m.width)("encoding", m.encoding);
  r("is_bigendian", m.is_bigendian)("step", m.step);
  r.seq("data", m.data);
}
void get(Reader& r, CameraInfo& m) {
  get(r, m.header);
  r("height", m.height)("width", m.width)("distortion_model", m.distortion_model);
  r.seq("d", m.d);
  r.array("k", m.k);
  r.array("r", m.r);
  r.array("p", m.p);
  r("binning_x", m.binning_x)("binning_y", m.binning_y);
  r("roi.x_offset", m.roi.x_offset)("roi.y_offset", m.roi.y_offset);
  r("roi.height", m.roi.height)("roi.width", m.roi.width)("roi.do_rectify", m.roi.do_rectify);
}
void get(Reader& r, Odometry& m) {
  get(r, m.header);
  r("child_frame_id", m.child_frame_id);
  r.field = "pose.pose";
  get(r, m.pose.pose);
  r.array("pose.covariance", m.pose.covariance);
  r.field = "twist.twist";
  get(r, m.twist.twist.linear);
  get(r, m.twist.twist.angular);
  r.array("twist.covariance", m.twist.covariance);
}
void get(Reader& r, PoseWithCovarianceStamped& m) {
  get(r, m.header);
  r.field = "pose.pose";
  get(r, m.pose.pose);
  r.array("pose.covariance", m.pose.covariance);
}
void get(Reader& r, TFMessage& m) {
  // header (12) + child_frame_id (4) + transform (56), the least a TransformStamped takes
  uint32_t n = r.count("transforms", 72);
  m.transforms.resize(n);
  for (TransformStamped& t : m.transforms) get(r, t);
}

template <class T>
Message decodeAs(std::span<const uint8_t> bytes) {
  // Fast-CDR only reads through this pointer; its API is not const-correct.
  fc::FastBuffer buffer(reinterpret_cast<char*>(const_cast<uint8_t*>(bytes.data())), bytes.size());
  fc::Cdr cdr(buffer, fc::Cdr::DEFAULT_ENDIAN, fc::Cdr::DDS_CDR);
  Reader r{cdr, bytes.size()};
  cdr.read_encapsulation();
  T m;
  try {
    get(r, m);
  } catch (const fc::exception::NotEnoughMemoryException&) {
    throw IoError("at " + std::string(r.field) + ": truncated, the message ends at byte " +
                  std::to_string(bytes.size()));
  } catch (const fc::exception::Exception& e) {
    throw IoError("at " + std::string(r.field) + " (byte " +
                  std::to_string(cdr.getSerializedDataLength()) + "): " + e.what());
  } catch (const IoError& e) {
    throw IoError("at byte " + std::to_string(cdr.getSerializedDataLength()) + ": " + e.what());
  }
  return m;
}

using Decoder = Message (*)(std::span<const uint8_t>);

}  // namespace

std::vector<uint8_t> encodeCdr(const Message& m) {
  std::vector<uint8_t> out(sizeHint(m));
  fc::FastBuffer buffer(reinterpret_cast<char*>(out.data()), out.size());
  fc::Cdr cdr(buffer, fc::Cdr::Endianness::LITTLE_ENDIANNESS, fc::Cdr::DDS_CDR);
  try {
    cdr.serialize_encapsulation();
    std::visit([&](const auto& v) { put(cdr, v); }, m);
  } catch (const fc::exception::Exception& e) {
    // Only a wrong size hint gets here: a bug, but still not a crash.
    throw IoError(std::string(typeName(m)) + ": CDR encoding failed: " + e.what());
  }
  out.resize(cdr.getSerializedDataLength());
  return out;
}

Message decodeCdr(const std::string& type_name, std::span<const uint8_t> bytes) {
  static const std::vector<std::pair<std::string, Decoder>> decoders = {
      {"sensor_msgs/msg/LaserScan", decodeAs<LaserScan>},
      {"sensor_msgs/msg/PointCloud2", decodeAs<PointCloud2>},
      {"sensor_msgs/msg/Image", decodeAs<Image>},
      {"sensor_msgs/msg/CameraInfo", decodeAs<CameraInfo>},
      {"nav_msgs/msg/Odometry", decodeAs<Odometry>},
      {"tf2_msgs/msg/TFMessage", decodeAs<TFMessage>},
      {"geometry_msgs/msg/PoseStamped", decodeAs<PoseStamped>},
      {"polyloc_msgs/msg/TrackArray", decodeAs<TrackArray>},
      {"geometry_msgs/msg/PoseWithCovarianceStamped", decodeAs<PoseWithCovarianceStamped>}};
  Decoder decode = nullptr;
  for (const auto& [name, d] : decoders)
    if (name == type_name) decode = d;
  if (!decode) throw IoError(type_name + ": CDR decoding failed: unknown message type");
  if (bytes.size() < 4)
    throw IoError(type_name + ": CDR decoding failed: truncated, " + std::to_string(bytes.size()) +
                  " bytes, not even the 4-byte encapsulation header");
  if (bytes[0] != 0 || bytes[1] > 1)  // 00 00: CDR big endian, 00 01: CDR little endian
    throw IoError(type_name + ": CDR decoding failed: unsupported encapsulation " +
                  std::to_string(bytes[0]) + " " + std::to_string(bytes[1]) +
                  " (expected plain CDR, 00 01 or 00 00)");
  try {
    return decode(bytes);
  } catch (const IoError& e) {
    throw IoError(type_name + ": CDR decoding failed " + e.what());
  } catch (const std::exception& e) {  // bad_alloc and Fast-CDR errors outside a field
    throw IoError(type_name + ": CDR decoding failed: " + e.what());
  }
}

}  // namespace polyloc::msg
