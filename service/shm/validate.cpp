// validateInput: every check reads only bytes the size checks before it have shown to be there,
// so it is safe on anything a slot holds (docs/interface.md, "Input validation").
#include "shm/validate.hpp"

#include <polyloc/geometry/domain_limits.hpp>

#include <cmath>
#include <cstring>
#include <string>

namespace polyloc::shm {
namespace {

template <class T> T field(const uint8_t* p, size_t offset) {
  T v;
  std::memcpy(&v, p + offset, sizeof v);  // the payload need not be aligned
  return v;
}

struct Check {
  const polyloc_channel_desc& channel;
  uint64_t frame;
  std::string prefix() const {
    return std::string(channel.name, strnlen(channel.name, POLYLOC_NAME_LEN)) + " frame " + std::to_string(frame) + ": ";
  }
  Validation fail(Reject r, const std::string& why) const { return {r, prefix() + why}; }
};

std::string str(uint64_t v) { return std::to_string(v); }

Validation ranges(const Check& c, const uint8_t* p, size_t bytes) {
  constexpr size_t head = offsetof(polyloc_ranges, ranges);
  if (bytes < head) return c.fail(Reject::Size, str(bytes) + " bytes, less than a scan's header (" + str(head) + ")");
  const uint32_t count = field<uint32_t>(p, offsetof(polyloc_ranges, count));
  if (c.channel.count && count != c.channel.count)
    return c.fail(Reject::Size, "count " + str(count) + ", expected " + str(c.channel.count) + " beams");
  const uint64_t expect = head + uint64_t{count} * sizeof(float);
  if (bytes != expect)
    return c.fail(Reject::Size, str(bytes) + " bytes, expected " + str(expect) + " for " + str(count) + " beams");
  for (uint32_t i = 0; i < count; ++i) {
    const float r = field<float>(p, head + i * sizeof(float));
    if (std::isfinite(r) && r >= 0 && r <= domain::kMaxRange) return {};
  }
  return c.fail(Reject::NaN, "none of the " + str(count) + " ranges is a distance (all NaN, inf, negative or beyond " +
                                 str(uint64_t(domain::kMaxRange)) + " m)");
}

Validation depth(const Check& c, const uint8_t* p, size_t bytes) {
  constexpr size_t head = offsetof(polyloc_depth, data);
  if (bytes < head) return c.fail(Reject::Size, str(bytes) + " bytes, less than a depth frame's header (" + str(head) + ")");
  const uint32_t w = field<uint32_t>(p, offsetof(polyloc_depth, width));
  const uint32_t h = field<uint32_t>(p, offsetof(polyloc_depth, height));
  const uint32_t amp = field<uint32_t>(p, offsetof(polyloc_depth, has_amplitude));
  if (w != c.channel.width || h != c.channel.height)
    return c.fail(Reject::Size, str(w) + "x" + str(h) + " pixels, expected " + str(c.channel.width) + "x" +
                                    str(c.channel.height));
  if (amp > 1) return c.fail(Reject::Size, "has_amplitude " + str(amp) + ", expected 0 or 1");
  const uint64_t expect = head + uint64_t{w} * h * sizeof(float) * (1 + amp);
  if (bytes != expect)
    return c.fail(Reject::Size, str(bytes) + " bytes, expected " + str(expect) + " for " + str(w) + "x" + str(h) +
                                    (amp ? " depth + amplitude" : " depth"));
  return {};
}

Validation odometry(const Check& c, const uint8_t* p, size_t bytes) {
  if (bytes != sizeof(polyloc_odometry))
    return c.fail(Reject::Size, str(bytes) + " bytes, expected " + str(sizeof(polyloc_odometry)) + " for odometry");
  const auto o = field<polyloc_odometry>(p, 0);
  const double pose[7] = {o.x, o.y, o.z, o.qw, o.qx, o.qy, o.qz};
  static const char* names[7] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  for (int i = 0; i < 7; ++i)
    if (!std::isfinite(pose[i])) return c.fail(Reject::NaN, std::string(names[i]) + " is " + std::to_string(pose[i]));
  // Finite is not enough: an odometry of 1e19 m would carry every particle off any map.
  for (int i = 0; i < 3; ++i)
    if (std::fabs(pose[i]) > domain::kMaxCoordinate)
      return c.fail(Reject::NaN, std::string(names[i]) + " is " + std::to_string(pose[i]) + ": beyond +-" +
                                     str(uint64_t(domain::kMaxCoordinate)) + " m");
  const double norm = std::sqrt(o.qw * o.qw + o.qx * o.qx + o.qy * o.qy + o.qz * o.qz);
  if (std::fabs(norm - 1.0) > 1e-3)
    return c.fail(Reject::NaN, "quaternion norm " + std::to_string(norm) + ", expected 1 within 1e-3");
  return {};
}

// Commands drive a base: what no base could execute is out of domain, not clamped (commandProblem).
Validation command(const Check& c, const uint8_t* p, size_t bytes) {
  if (bytes != sizeof(polyloc_command))
    return c.fail(Reject::Size, str(bytes) + " bytes, expected " + str(sizeof(polyloc_command)) + " for a command");
  const auto m = field<polyloc_command>(p, 0);
  if (std::string why = commandProblem(m.vx, m.vy, m.wz, m.nav_state); !why.empty()) return c.fail(Reject::NaN, why);
  if (std::memchr(m.status, 0, sizeof m.status) == nullptr) return c.fail(Reject::Size, "status is not NUL-terminated");
  return {};
}

}  // namespace

std::string commandProblem(double vx, double vy, double wz, uint32_t nav_state) {
  const double v[3] = {vx, vy, wz};
  static const char* names[3] = {"vx", "vy", "wz"};
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]) || std::fabs(v[i]) > POLYLOC_COMMAND_MAX)
      return std::string(names[i]) + " is " + std::to_string(v[i]) + ": not within +-" + std::to_string(int(POLYLOC_COMMAND_MAX));
  if (nav_state > POLYLOC_NAV_FAILED) return "nav_state " + std::to_string(nav_state) + ", expected 0..3";
  return {};
}

namespace {

// a < b - d and a > b + d without overflowing int64.
bool olderThan(int64_t a, int64_t b, int64_t d) { return static_cast<__int128>(a) < static_cast<__int128>(b) - d; }
bool laterThan(int64_t a, int64_t b, int64_t d) { return static_cast<__int128>(a) > static_cast<__int128>(b) + d; }

Validation stamps(const Check& c, int64_t stamp, const StampRules& r) {
  // 0 means "no frame yet" in every health and status field; a time before 1970 is no sensor's.
  if (stamp <= 0) return c.fail(Reject::Stale, "stamp " + std::to_string(stamp) + " ns is not a time (stamps are > 0)");
  if (r.last_ns != INT64_MIN && stamp <= r.last_ns)
    return c.fail(Reject::Stale, "stamp " + std::to_string(stamp) + " ns is not after the last frame's " +
                                     std::to_string(r.last_ns));
  if (r.max_age_ns >= 0 && olderThan(stamp, r.now_ns, r.max_age_ns))
    return c.fail(Reject::Stale, "stamp " + std::to_string(stamp) + " ns is " +
                                     std::to_string(static_cast<double>(r.now_ns - static_cast<__int128>(stamp)) * 1e-6) +
                                     " ms old (max_age " + std::to_string(r.max_age_ns / 1'000'000) + " ms)");
  if (r.max_future_ns >= 0 && laterThan(stamp, r.now_ns, r.max_future_ns))
    return c.fail(Reject::Future, "stamp " + std::to_string(stamp) + " ns is " +
                                      std::to_string(static_cast<double>(stamp - static_cast<__int128>(r.now_ns)) * 1e-6) +
                                      " ms in the future (max_future " + std::to_string(r.max_future_ns / 1'000'000) + " ms)");
  return {};
}

}  // namespace

const char* toString(Reject r) {
  switch (r) {
    case Reject::None: return "ok";
    case Reject::Size: return "size";
    case Reject::NaN: return "nan";
    case Reject::Stale: return "stale";
    case Reject::Future: return "future";
  }
  return "?";
}

Validation validateInput(const polyloc_channel_desc& channel, uint64_t frame, const uint8_t* payload, size_t bytes,
                         const StampRules& rules) {
  const Check c{channel, frame};
  // First, before any byte is read: a size field beyond the slot is a broken writer.
  if (bytes > channel.payload_max)
    return c.fail(Reject::Size, "size field " + str(bytes) + " bytes exceeds the channel's capacity of " +
                                    str(channel.payload_max));
  Validation v;
  switch (channel.kind) {
    case POLYLOC_KIND_RANGES: v = ranges(c, payload, bytes); break;
    case POLYLOC_KIND_DEPTH: v = depth(c, payload, bytes); break;
    case POLYLOC_KIND_ODOMETRY: v = odometry(c, payload, bytes); break;
    case POLYLOC_KIND_COMMAND: v = command(c, payload, bytes); break;
    default: return c.fail(Reject::Size, "kind " + str(channel.kind) + " is not an input kind");
  }
  if (!v) return v;
  // Every input payload starts with its stamp (the size checks above cover it).
  return stamps(c, field<int64_t>(payload, 0), rules);
}

}  // namespace polyloc::shm
