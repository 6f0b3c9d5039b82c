#include "protocol/messages.hpp"

#include "protocol/words.hpp"

#include <cmath>
#include <limits>

namespace polyloc::protocol {
namespace {

void putPose6(WordWriter& w, const Pose& p) {
  w.f32(p.x()), w.f32(p.y()), w.f32(p.z());
  w.f32(p.roll()), w.f32(p.pitch()), w.f32(p.yaw());
}

Pose getPose6(WordReader& r) {
  const double x = r.f32(), y = r.f32(), z = r.f32();
  const double roll = r.f32(), pitch = r.f32(), yaw = r.f32();
  return Pose::fromXYZRPY(x, y, z, roll, pitch, yaw);
}

template <class T>
std::optional<T> doneOr(const WordReader& r, T value) {
  if (!r.done()) return std::nullopt;
  return value;
}

// A count read from the wire is only believed if that many entries of at least `words` words
// can follow, so a corrupt count never makes a decoder allocate much.
bool plausibleCount(const WordReader& r, uint32_t n, size_t words) { return r.ok() && n <= r.remaining() / words; }

// The stamp and entry count that open the scan and track replies.
void putStampAndCount(WordWriter& w, int64_t stamp, size_t n) {
  w.i64(stamp);
  w.u32(static_cast<uint32_t>(n));
}

std::optional<uint32_t> stampAndCount(WordReader& r, int64_t& stamp, size_t entry_words) {
  stamp = r.i64();
  const uint32_t n = r.u32();
  if (!plausibleCount(r, n, entry_words)) return std::nullopt;
  return n;
}

}  // namespace

Words encodeSeed(const PoseSeed& s) {
  WordWriter w;
  w.f32(s.x), w.f32(s.y), w.f32(s.yaw);
  if (s.sigma_xy_m || s.sigma_yaw_rad) {
    // Both or neither on the wire; a missing one is sent as 0, read back as "default".
    w.f32(s.sigma_xy_m.value_or(0)), w.f32(s.sigma_yaw_rad.value_or(0));
  }
  return w.take();
}

std::optional<PoseSeed> decodeSeed(WordSpan data) {
  if (data.size() != 3 && data.size() != 5) return std::nullopt;
  WordReader r(data);
  const double x = r.f32(), y = r.f32(), yaw = r.f32();
  PoseSeed s{x, y, yaw, {}, {}};
  if (data.size() == 5) {
    const double sxy = r.f32(), syaw = r.f32();
    if (sxy != 0) s.sigma_xy_m = sxy;
    if (syaw != 0) s.sigma_yaw_rad = syaw;
  }
  return doneOr(r, s);
}

Words encodePlanarPose(const PoseReport& p) {
  WordWriter w;
  w.f32(p.pose.x()), w.f32(p.pose.y()), w.f32(p.pose.yaw());
  w.i64(p.stamp_ns);
  return w.take();
}

std::optional<PoseReport> decodePlanarPose(WordSpan data) {
  WordReader r(data);
  PoseReport p;
  const double x = r.f32(), y = r.f32(), yaw = r.f32();
  p.pose = Pose::planar(x, y, yaw);
  p.stamp_ns = r.i64();
  p.status = PoseStatus::Tracking;  // not on the wire; the reply status qualifies it
  return doneOr(r, p);
}

Words encodePoseCovariance(const PoseReport& p) {
  WordWriter w;
  w.u32(static_cast<uint32_t>(p.status));
  w.i64(p.stamp_ns);
  putPose6(w, p.pose);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) w.f32(p.covariance(i, j));
  w.f32(p.ess);
  w.u32(p.particles);
  return w.take();
}

std::optional<PoseReport> decodePoseCovariance(WordSpan data) {
  WordReader r(data);
  PoseReport p;
  const uint32_t status = r.u32();
  if (status > static_cast<uint32_t>(PoseStatus::Lost)) return std::nullopt;
  p.status = static_cast<PoseStatus>(status);
  p.stamp_ns = r.i64();
  p.pose = getPose6(r);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) p.covariance(i, j) = r.f32();
  p.ess = r.f32();
  p.particles = r.u32();
  return doneOr(r, p);
}

Words encodeMount(const Pose& mount) {
  WordWriter w;
  putPose6(w, mount);
  return w.take();
}

std::optional<Pose> decodeMount(WordSpan data) {
  WordReader r(data);
  const Pose p = getPose6(r);
  return doneOr(r, p);
}

Words encodeScanners(const std::vector<ScannerInfo>& scanners) {
  WordWriter w;
  w.u32(static_cast<uint32_t>(scanners.size()));
  for (const auto& s : scanners) {
    putPose6(w, s.mount);
    w.u32(s.beams);
    w.str(s.name);
  }
  return w.take();
}

std::optional<std::vector<ScannerInfo>> decodeScanners(WordSpan data) {
  WordReader r(data);
  const uint32_t n = r.u32();
  if (!plausibleCount(r, n, 8)) return std::nullopt;
  std::vector<ScannerInfo> out(n);
  for (auto& s : out) {
    s.mount = getPose6(r);
    s.beams = r.u32();
    s.name = r.str();
  }
  return doneOr(r, std::move(out));
}

Words encodeScan(const PolarScan& scan) {
  WordWriter w;
  const size_t n = std::min(scan.angles.size(), scan.ranges.size());
  putStampAndCount(w, scan.stamp_ns, n);
  for (size_t i = 0; i < n; ++i) {
    // One spelling of "no return" on the wire, whatever the sensor reported.
    const float range = scan.ranges[i];
    w.f32(scan.angles[i]);
    w.f32(std::isfinite(range) && range >= 0 ? range : std::numeric_limits<float>::infinity());
  }
  return w.take();
}

std::optional<PolarScan> decodeScan(WordSpan data) {
  WordReader r(data);
  PolarScan s;
  const auto n = stampAndCount(r, s.stamp_ns, 2);
  if (!n) return std::nullopt;
  s.angles.resize(*n), s.ranges.resize(*n);
  for (uint32_t i = 0; i < *n; ++i) s.angles[i] = r.f32(), s.ranges[i] = r.f32();
  return doneOr(r, std::move(s));
}

Words encodeTracks(const TrackList& t) {
  WordWriter w;
  putStampAndCount(w, t.stamp_ns, t.tracks.size());
  for (const auto& k : t.tracks) {
    w.u32(k.id), w.u32(k.confirmed ? 1 : 0);
    w.f32(k.x), w.f32(k.y), w.f32(k.vx), w.f32(k.vy);
    for (double c : k.covariance) w.f32(c);
  }
  return w.take();
}

std::optional<TrackList> decodeTracks(WordSpan data) {
  WordReader r(data);
  TrackList t;
  const auto n = stampAndCount(r, t.stamp_ns, 10);
  if (!n) return std::nullopt;
  t.tracks.resize(*n);
  for (auto& k : t.tracks) {
    k.id = r.u32(), k.confirmed = r.u32() != 0;
    k.x = r.f32(), k.y = r.f32(), k.vx = r.f32(), k.vy = r.f32();
    for (double& c : k.covariance) c = r.f32();
  }
  return doneOr(r, std::move(t));
}

Words encodeHealth(const HealthReport& h) {
  WordWriter w;
  w.i64(h.stamp_ns);
  w.f32(h.uptime_s);
  w.u32(static_cast<uint32_t>(h.pose_status));
  w.u64(h.cycles), w.u64(h.poses), w.u64(h.vrs), w.u64(h.tracks);
  w.f32(h.pose_rate_hz), w.f32(h.cycle_p50_ms), w.f32(h.cycle_p99_ms);
  w.u32(static_cast<uint32_t>(h.inputs.size()));
  for (const auto& in : h.inputs) {
    w.f32(in.rate_hz);
    w.u64(in.taken), w.u64(in.rejected);
    w.f32(in.silence_s);
    w.u32(in.silent ? 1 : 0);
    w.str(in.name);
  }
  // Protocol 1.1 appends the map fit: u32 unfit, then per input f32 map_fit (-1: not measured).
  w.u32(h.unfit ? 1 : 0);
  for (const auto& in : h.inputs) w.f32(in.map_fit);
  return w.take();
}

std::optional<HealthReport> decodeHealth(WordSpan data) {
  WordReader r(data);
  HealthReport h;
  h.stamp_ns = r.i64();
  h.uptime_s = r.f32();
  const uint32_t status = r.u32();
  if (status > static_cast<uint32_t>(PoseStatus::Lost)) return std::nullopt;
  h.pose_status = static_cast<PoseStatus>(status);
  h.cycles = r.u64(), h.poses = r.u64(), h.vrs = r.u64(), h.tracks = r.u64();
  h.pose_rate_hz = r.f32(), h.cycle_p50_ms = r.f32(), h.cycle_p99_ms = r.f32();
  const uint32_t n = r.u32();
  if (!plausibleCount(r, n, 8)) return std::nullopt;
  h.inputs.resize(n);
  for (auto& in : h.inputs) {
    in.rate_hz = r.f32();
    in.taken = r.u64(), in.rejected = r.u64();
    in.silence_s = r.f32();
    in.silent = r.u32() != 0;
    in.name = r.str();
  }
  if (r.ok() && !r.done()) {  // a 1.1 server: the map fit follows (a 1.0 reply ends here)
    h.unfit = r.u32() != 0;
    for (auto& in : h.inputs) in.map_fit = r.f32();
  }
  return doneOr(r, std::move(h));
}

}  // namespace polyloc::protocol
