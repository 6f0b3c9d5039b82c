// CARMEN logs (the text format of the CARMEN toolkit and of the classic Freiburg/Intel/MIT
// datasets), plain or gzip, read line by line through zlib (gzopen reads plain files as they
// are). Mapping to ROS 2 messages, and what is ignored, is in docs/recordings.md.
// Messages come in file order: the CARMEN logger writes each message as it arrives, so a log
// is in time order by construction.
#include <polyloc/geometry/domain_limits.hpp>
#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/recording.hpp>

#include "decimal_seconds.hpp"

#include <zlib.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string_view>

namespace polyloc {
namespace {

constexpr int kMaxReadings = 100000;           // more is not a laser scanner: the line is corrupt
constexpr size_t kMaxLineBytes = 16u << 20;    // longer lines are binary garbage, not a message
constexpr size_t kMaxUnknownTypes = 1000;      // keeps memory flat on garbage input

// Lines of a plain or gzip file, streamed in 64 KiB blocks. Lines may hold any byte (a
// bit-flipped log); a line longer than kMaxLineBytes is cut and flagged.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), buf_(1 << 16) {
    file_ = gzopen(path.c_str(), "rb");
    if (!file_) throw IoError(path + ": cannot open: " + std::strerror(errno));
    gzbuffer(file_, 1 << 17);
  }
  ~LineReader() { gzclose(file_); }
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // False at the end. `too_long` is set when the line was cut.
  bool getline(std::string& line, bool& too_long) {
    line.clear();
    too_long = false;
    bool any = false;
    for (;;) {
      if (pos_ == len_ && !refill()) return any;
      any = true;
      const char* begin = buf_.data() + pos_;
      const void* nl = std::memchr(begin, '\n', len_ - pos_);
      const size_t n = nl ? static_cast<const char*>(nl) - begin : len_ - pos_;
      if (line.size() + n <= kMaxLineBytes)
        line.append(begin, n);
      else
        too_long = true;
      pos_ += n;
      if (nl) {
        ++pos_;
        return true;
      }
    }
  }
  // The zlib error that ended reading early (corrupt or truncated gzip), empty if none.
  const std::string& error() const { return error_; }

 private:
  bool refill() {
    if (eof_) return false;
    const int n = gzread(file_, buf_.data(), static_cast<unsigned>(buf_.size()));
    if (n <= 0) {
      eof_ = true;
      int err = Z_OK;
      const char* msg = gzerror(file_, &err);
      if (err != Z_OK) error_ = msg ? msg : "zlib error";  // Z_BUF_ERROR: truncated gzip
      return false;
    }
    pos_ = 0;
    len_ = static_cast<size_t>(n);
    return true;
  }

  std::string path_;
  gzFile file_ = nullptr;
  std::vector<char> buf_;
  size_t pos_ = 0, len_ = 0;
  bool eof_ = false;
  std::string error_;
};

bool parseDouble(std::string_view s, double& v) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}
bool parseFinite(std::string_view s, double& v) { return parseDouble(s, v) && std::isfinite(v); }
bool parseInt(std::string_view s, long& v) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && p == s.data() + s.size();
}

// Printable and short, for naming bad tokens in warnings.
std::string quote(std::string_view s) {
  std::string out = "'";
  for (char c : s.substr(0, 32)) out += (c >= 32 && c < 127) ? c : '?';
  return out + (s.size() > 32 ? "...'" : "'");
}

msg::Quaternion yawQuaternion(double yaw) { return {0, 0, std::sin(yaw / 2), std::cos(yaw / 2)}; }

// Old-style FLASER/RLASER scanner geometry; CARMEN PARAM lines (laser_front_laser_fov,
// laser_front_laser_resolution in degrees, robot_front_laser_max in metres; rear alike) override.
struct LaserParams {
  double fov_deg = 180.0;
  double resolution_deg = 0.0;  // 0: 1 deg up to 181 beams, else fov / (n - 1)
  double max_range = 80.0;
};

// Where odometry comes from: ODOM lines; without any, the odometry fields of the scans
// (FLASER, else RLASER, else ROBOTLASER1's robot pose), which raw logs carry with every scan.
enum class OdometrySource { Odom, Flaser, Rlaser, RobotLaser, None };

OdometrySource findOdometrySource(const std::string& path) {
  LineReader lines(path);
  std::string line;
  bool too_long = false, flaser = false, rlaser = false, robot = false;
  while (lines.getline(line, too_long)) {
    if (line.starts_with("ODOM ")) return OdometrySource::Odom;
    flaser = flaser || line.starts_with("FLASER ");
    rlaser = rlaser || line.starts_with("RLASER ");
    robot = robot || line.starts_with("ROBOTLASER1 ");
  }
  return flaser ? OdometrySource::Flaser : rlaser ? OdometrySource::Rlaser : robot ? OdometrySource::RobotLaser : OdometrySource::None;
}

// One pass over a log: lines in, RecordedMessages out.
class CarmenSource {
 public:
  CarmenSource(const std::string& path, OdometrySource odometry) : path_(path), lines_(path), odometry_(odometry) {}

  bool next(RecordedMessage& out, ReadStats& stats) {
    while (pending_.empty()) {
      bool too_long = false;
      if (!lines_.getline(line_, too_long)) {
        if (!lines_.error().empty() && !reported_error_) {
          reported_error_ = true;
          stats.warn(path_ + ":" + std::to_string(line_no_) + ": gzip data corrupt or truncated (" +
                     lines_.error() + "); reading stopped here");
        }
        return false;
      }
      ++line_no_;
      if (too_long) {
        stats.warn(where() + "line longer than 16 MiB, skipped");
        continue;
      }
      parseLine(stats);
    }
    out = std::move(pending_.front());
    pending_.pop_front();
    ++stats.messages;
    return true;
  }

 private:
  std::string where() const { return path_ + ":" + std::to_string(line_no_) + ": "; }

  void parseLine(ReadStats& stats) {
    std::string_view v(line_);
    if (!v.empty() && v.back() == '\r') v.remove_suffix(1);
    t_.clear();
    for (size_t i = 0; i < v.size();) {
      while (i < v.size() && (v[i] == ' ' || v[i] == '\t')) ++i;
      size_t j = i;
      while (j < v.size() && v[j] != ' ' && v[j] != '\t') ++j;
      if (j > i) t_.push_back(v.substr(i, j - i));
      i = j;
    }
    if (t_.empty() || t_[0][0] == '#') return;
    const std::string_view type = t_[0];
    if (type == "FLASER") return oldLaser(stats, "/front_laser", "front_laser", front_);
    if (type == "RLASER") return oldLaser(stats, "/rear_laser", "rear_laser", rear_);
    if (type == "ROBOTLASER1") return robotLaser(stats);
    if (type == "ODOM") return odom(stats);
    if (type == "PARAM") return param(stats);
    if (type == "SYNC" || type.starts_with("NMEA")) return;
    bool word = type.size() <= 32;  // a message name, or a garbled line?
    for (char c : type) word = word && ((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_');
    if (!word) return stats.warn(where() + "not a CARMEN message: starts with " + quote(type));
    if (unknown_.size() < kMaxUnknownTypes && unknown_.insert(std::string(type)).second)
      stats.warn(where() + std::string(type) + ": message type not supported, skipped (warned once)");
  }

  void param(ReadStats& stats) {
    if (t_.size() < 3) return;
    double v = 0;
    if (!parseFinite(t_[2], v)) return;
    const std::string_view name = t_[1];
    // The field of view is in degrees; some logs (MIT's csail) write radians (3.14159). No laser
    // scanner has a field of view of a few degrees.
    if (name.ends_with("_laser_fov") && v > 0 && v <= 2 * M_PI + 1e-3) {
      stats.note(where() + std::string(name) + " " + std::string(t_[2]) + ": taken as radians (" +
                 std::to_string(int(std::lround(rad2deg(v)))) + " deg)");
      v = rad2deg(v);
    }
    if (name == "laser_front_laser_fov") front_.fov_deg = v;
    if (name == "laser_front_laser_resolution") front_.resolution_deg = v;
    if (name == "robot_front_laser_max") front_.max_range = v;
    if (name == "laser_rear_laser_fov") rear_.fov_deg = v;
    if (name == "laser_rear_laser_resolution") rear_.resolution_deg = v;
    if (name == "robot_rear_laser_max") rear_.max_range = v;
  }

  // Parses fields [first, first + n) as finite numbers into out; warns and returns false if not.
  // Every number a CARMEN line holds (poses, speeds, angles, ranges limits) is within +-1e6: a
  // larger one is a corrupt line, not a pose to carry particles to (docs/failure.md).
  bool numbers(ReadStats& stats, size_t first, size_t n, double* out) {
    for (size_t k = 0; k < n; ++k) {
      if (!parseFinite(t_[first + k], out[k])) {
        stats.warn(where() + std::string(t_[0]) + ": field " + std::to_string(first + k) +
                   " is not a number: " + quote(t_[first + k]));
        return false;
      }
      if (std::fabs(out[k]) > domain::kMaxCoordinate) {
        stats.warn(where() + std::string(t_[0]) + ": field " + std::to_string(first + k) + " is " +
                   quote(t_[first + k]) + ": beyond +-1e6, line skipped");
        return false;
      }
    }
    return true;
  }
  // num_readings-like count at field i, 0..kMaxReadings.
  std::optional<size_t> count(ReadStats& stats, size_t i, const char* what) {
    long n = -1;
    if (!parseInt(t_[i], n) || n < 0 || n > kMaxReadings) {
      stats.warn(where() + std::string(t_[0]) + ": " + what + " " + quote(t_[i]) +
                 " is not a count in 0.." + std::to_string(kMaxReadings));
      return std::nullopt;
    }
    return static_cast<size_t>(n);
  }
  bool ranges(ReadStats& stats, size_t first, size_t n, std::vector<float>& out) {
    out.resize(n);
    for (size_t k = 0; k < n; ++k) {
      double r = 0;  // NaN and inf are legal ranges (no return)
      if (!parseDouble(t_[first + k], r)) {
        stats.warn(where() + std::string(t_[0]) + ": reading " + std::to_string(k) +
                   " is not a number: " + quote(t_[first + k]));
        return false;
      }
      out[k] = static_cast<float>(r);
    }
    return true;
  }
  // The trailing "ipc_timestamp ipc_hostname logger_timestamp" starting at field i.
  std::optional<int64_t> stamp(ReadStats& stats, size_t i) {
    const auto ns = io_detail::parseSecondsNs(t_[i]);
    double logger = 0;
    if (!ns || !parseFinite(t_[i + 2], logger)) {
      stats.warn(where() + std::string(t_[0]) + ": bad timestamp " + quote(ns ? t_[i + 2] : t_[i]));
      return std::nullopt;
    }
    // Kept (a log's order is its order; --restamp orders by place), but said once.
    if (last_ns_ && *ns < *last_ns_ && !noted_backwards_) {
      noted_backwards_ = true;
      stats.note(where() + "time goes backwards (" + std::string(t_[i]) + " s after " +
                 std::to_string(double(*last_ns_) * 1e-9) + " s); later occurrences are not noted");
    }
    last_ns_ = ns;
    return ns;
  }
  void emit(const std::string& topic, int64_t ns, msg::Message m) {
    pending_.push_back(RecordedMessage{topic, ns, ns, std::move(m)});
  }
  // The logged laser pose (corrected logs: the known pose), right after its scan on
  // <scan topic>_pose, so that a consumer pairs a scan with the next message on that topic.
  void emitPose(const std::string& scan_topic, int64_t ns, double x, double y, double yaw) {
    msg::PoseStamped p;
    p.header = {msg::fromNs(ns), "world"};
    p.pose.position = {x, y, 0};
    p.pose.orientation = yawQuaternion(yaw);
    emit(scan_topic + "_pose", ns, std::move(p));
  }

  // FLASER/RLASER num_readings [ranges] x y theta odom_x odom_y odom_theta ipc_ts host logger_ts
  void oldLaser(ReadStats& stats, const std::string& topic, const char* frame, const LaserParams& p) {
    if (t_.size() < 11) {
      stats.warn(where() + std::string(t_[0]) + ": expected at least 11 fields, got " +
                 std::to_string(t_.size()));
      return;
    }
    const auto n = count(stats, 1, "num_readings");
    if (!n) return;
    if (t_.size() != *n + 11) {
      stats.warn(where() + std::string(t_[0]) + ": expected " + std::to_string(*n) + " ranges, got " +
                 std::to_string(t_.size() - 11));
      return;
    }
    msg::LaserScan scan;
    double poses[6];  // laser pose in the world (published), odometry pose (validated only)
    if (!ranges(stats, 2, *n, scan.ranges) || !numbers(stats, 2 + *n, 6, poses)) return;
    const auto ns = stamp(stats, 8 + *n);
    if (!ns) return;
    const double fov = deg2rad(p.fov_deg);
    const double inc = p.resolution_deg > 0 ? deg2rad(p.resolution_deg)
                       : *n <= 181 || *n < 2 ? deg2rad(1.0)
                                             : fov / double(*n - 1);
    scan.header = {msg::fromNs(*ns), frame};
    scan.angle_min = static_cast<float>(-fov / 2);
    scan.angle_increment = static_cast<float>(inc);
    scan.angle_max = static_cast<float>(-fov / 2 + inc * (*n > 0 ? double(*n - 1) : 0.0));
    scan.range_max = static_cast<float>(p.max_range);
    // The scan's odometry first: a consumer then has it when the scan comes.
    if ((odometry_ == OdometrySource::Flaser && topic == "/front_laser") ||
        (odometry_ == OdometrySource::Rlaser && topic == "/rear_laser"))
      emitOdometry(*ns, poses[3], poses[4], poses[5], 0, 0, stats);
    emit(topic, *ns, std::move(scan));
    emitPose(topic, *ns, poses[0], poses[1], poses[2]);
  }

  // ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode
  //   n [ranges] m [remissions] laser_x laser_y laser_theta robot_x robot_y robot_theta
  //   tv rv forward_safety side_safety turn_axis ipc_ts host logger_ts
  void robotLaser(ReadStats& stats) {
    if (t_.size() < 24) {
      stats.warn(where() + "ROBOTLASER1: expected at least 24 fields, got " + std::to_string(t_.size()));
      return;
    }
    double head[6];
    if (!numbers(stats, 2, 6, head)) return;
    const auto n = count(stats, 8, "num_readings");
    if (!n) return;
    if (t_.size() < *n + 24) {
      stats.warn(where() + "ROBOTLASER1: expected " + std::to_string(*n) + " ranges, got " +
                 std::to_string(t_.size() - 24));
      return;
    }
    const auto m = count(stats, 9 + *n, "num_remissions");
    if (!m) return;
    if (t_.size() != *n + *m + 24) {
      stats.warn(where() + "ROBOTLASER1: expected " + std::to_string(*n + *m + 24) + " fields for " +
                 std::to_string(*n) + " ranges and " + std::to_string(*m) + " remissions, got " +
                 std::to_string(t_.size()));
      return;
    }
    msg::LaserScan scan;
    std::vector<float> remissions;
    double tail[11];  // laser pose, robot pose, tv rv, safety distances, turn axis
    const size_t after = 10 + *n + *m;
    if (!ranges(stats, 9, *n, scan.ranges) || !ranges(stats, 10 + *n, *m, remissions) ||
        !numbers(stats, after, 11, tail))
      return;
    const auto ns = stamp(stats, after + 11);
    if (!ns) return;
    if (remissions.size() == scan.ranges.size()) scan.intensities = std::move(remissions);
    scan.header = {msg::fromNs(*ns), "laser"};
    scan.angle_min = static_cast<float>(head[0]);
    scan.angle_increment = static_cast<float>(head[2]);
    scan.angle_max = static_cast<float>(head[0] + head[2] * (*n > 0 ? double(*n - 1) : 0.0));
    scan.range_max = static_cast<float>(head[3]);

    // Laser pose in the robot frame, from the two world poses; published when it changes.
    const double dx = tail[0] - tail[3], dy = tail[1] - tail[4], c = std::cos(tail[5]), s = std::sin(tail[5]);
    const double mount[3] = {c * dx + s * dy, -s * dx + c * dy, wrapAngle(tail[2] - tail[5])};
    if (!mount_ || std::fabs(mount[0] - (*mount_)[0]) > 1e-3 || std::fabs(mount[1] - (*mount_)[1]) > 1e-3 ||
        std::fabs(angleDiff(mount[2], (*mount_)[2])) > 1e-3) {
      mount_ = {mount[0], mount[1], mount[2]};
      msg::TransformStamped tf;
      tf.header = {msg::fromNs(*ns), "base_link"};
      tf.child_frame_id = "laser";
      tf.transform.translation = {mount[0], mount[1], 0};
      tf.transform.rotation = yawQuaternion(mount[2]);
      emit("/tf", *ns, msg::TFMessage{{tf}});
    }
    if (odometry_ == OdometrySource::RobotLaser) emitOdometry(*ns, tail[3], tail[4], tail[5], tail[6], tail[7], stats);
    emit("/robot_laser", *ns, std::move(scan));
    emitPose("/robot_laser", *ns, tail[0], tail[1], tail[2]);
  }

  // /odom from a scan's odometry fields (a log without ODOM lines).
  void emitOdometry(int64_t ns, double x, double y, double yaw, double tv, double rv, ReadStats& stats) {
    if (!noted_odometry_) {
      noted_odometry_ = true;
      stats.note(path_ + ": no ODOM lines: /odom is the odometry pose of each " +
                 std::string(t_[0]) + " line");
    }
    emitOdometryMessage(ns, x, y, yaw, tv, rv);
  }
  void emitOdometryMessage(int64_t ns, double x, double y, double yaw, double tv, double rv) {
    msg::Odometry o;
    o.header = {msg::fromNs(ns), "odom"};
    o.child_frame_id = "base_link";
    o.pose.pose.position = {x, y, 0};
    o.pose.pose.orientation = yawQuaternion(yaw);
    o.twist.twist.linear.x = tv;
    o.twist.twist.angular.z = rv;
    emit("/odom", ns, std::move(o));
  }

  // ODOM x y theta tv rv accel ipc_ts host logger_ts
  void odom(ReadStats& stats) {
    if (t_.size() != 10) {
      stats.warn(where() + "ODOM: expected 10 fields, got " + std::to_string(t_.size()));
      return;
    }
    double f[6];
    if (!numbers(stats, 1, 6, f)) return;
    const auto ns = stamp(stats, 7);
    if (!ns) return;
    emitOdometryMessage(*ns, f[0], f[1], f[2], f[3], f[4]);
  }

  std::string path_;
  LineReader lines_;
  OdometrySource odometry_;
  bool noted_odometry_ = false;
  bool noted_backwards_ = false;
  std::optional<int64_t> last_ns_;
  std::string line_;
  std::vector<std::string_view> t_;
  uint64_t line_no_ = 0;
  bool reported_error_ = false;
  LaserParams front_, rear_;
  std::optional<std::array<double, 3>> mount_;
  std::set<std::string> unknown_;
  std::deque<RecordedMessage> pending_;
};

class CarmenReader final : public RecordingReader {
 public:
  explicit CarmenReader(const std::string& path)
      : path_(path), odometry_(findOdometrySource(path)), source_(path, odometry_) {}

  std::vector<TopicInfo> topics() override {
    if (topics_) return *topics_;
    CarmenSource pass(path_, odometry_);  // own file handle: next() on source_ is not disturbed
    ReadStats ignored;
    RecordedMessage m;
    TopicTally tally;
    while (pass.next(m, ignored)) tally.add(m);
    topics_ = tally.topics();
    return *topics_;
  }
  bool next(RecordedMessage& out) override { return source_.next(out, stats_); }
  const ReadStats& stats() const override { return stats_; }
  std::string format() const override { return "carmen"; }

 private:
  std::string path_;
  OdometrySource odometry_;
  CarmenSource source_;
  ReadStats stats_;
  std::optional<std::vector<TopicInfo>> topics_;
};

}  // namespace

std::unique_ptr<RecordingReader> openCarmen(const std::string& path) {
  return std::make_unique<CarmenReader>(path);
}

}  // namespace polyloc
