// The payload structs of polyloc_shm.h <-> dicts of numpy arrays and Poses (shm_dicts.hpp).
#include "shm_dicts.hpp"

#include "shm/validate.hpp"

#include <polyloc/geometry/pose.hpp>
#include <polyloc/mcl/localizer.hpp>  // MclStatus names: pose status strings as polyloc.Localizer's

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <optional>

namespace polyloc::py {

namespace shm_dicts_impl {  // named, not anonymous: the module is compiled in batches (unity build)

uint32_t kindOf(const pb::handle& v) {
  if (pb::isinstance<pb::int_>(v)) return v.cast<uint32_t>();
  const std::string s = v.cast<std::string>();
  for (uint32_t k : {POLYLOC_KIND_RANGES, POLYLOC_KIND_DEPTH, POLYLOC_KIND_ODOMETRY, POLYLOC_KIND_COMMAND, POLYLOC_KIND_POSE,
                     POLYLOC_KIND_VRS, POLYLOC_KIND_TRACKS, POLYLOC_KIND_HEALTH})
    if (s == kindName(k)) return k;
  raise(PyExc_ValueError, "channel kind '" + s + "': one of ranges, depth, odometry, command, pose, vrs, tracks, health");
}

const char* const kNavStates[] = {"idle", "driving", "reached", "failed"};  // POLYLOC_NAV_* order

template <class T>
T fixedPart(const std::vector<uint8_t>& buf) {
  T v{};
  std::memcpy(&v, buf.data(), std::min(sizeof(T), buf.size()));
  return v;
}

pb::array_t<float> floats(const uint8_t* p, std::vector<pb::ssize_t> shape) {
  pb::array_t<float> a(shape);
  std::memcpy(a.mutable_data(), p, static_cast<size_t>(a.size()) * sizeof(float));
  return a;
}

// x y z, qw qx qy qz as the structs hold them.
Pose quaternionPose(double x, double y, double z, double qw, double qx, double qy, double qz) {
  const Eigen::Quaterniond q(qw, qx, qy, qz);  // a zero quaternion (a frame never filled in): no rotation
  return Pose(q.norm() > 0 ? q.normalized() : Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, z));
}

void putPose(const Pose& p, double* xyz, double* wxyz) {
  const auto& t = p.translation();
  const auto& q = p.rotation();
  xyz[0] = t.x(), xyz[1] = t.y(), xyz[2] = t.z();
  wxyz[0] = q.w(), wxyz[1] = q.x(), wxyz[2] = q.y(), wxyz[3] = q.z();
}

MclStatus statusOf(const std::string& s) {
  for (auto v : {MclStatus::Initialising, MclStatus::Tracking, MclStatus::Uncertain, MclStatus::Lost})
    if (s == toString(v)) return v;
  raise(PyExc_ValueError, "status '" + s + "': one of initialising, tracking, uncertain, lost");
}

template <class T> T get(const pb::dict& d, const char* key, T def) { return d.contains(key) ? d[key].cast<T>() : def; }

}  // namespace shm_dicts_impl

const char* kindName(uint32_t k) {
  using namespace shm_dicts_impl;
  switch (k) {
    case POLYLOC_KIND_RANGES: return "ranges";
    case POLYLOC_KIND_DEPTH: return "depth";
    case POLYLOC_KIND_ODOMETRY: return "odometry";
    case POLYLOC_KIND_COMMAND: return "command";
    case POLYLOC_KIND_POSE: return "pose";
    case POLYLOC_KIND_VRS: return "vrs";
    case POLYLOC_KIND_TRACKS: return "tracks";
    case POLYLOC_KIND_HEALTH: return "health";
    default: return "unknown";
  }
}

std::string channelName(const polyloc_channel_desc& d) { return std::string(d.name, strnlen(d.name, POLYLOC_NAME_LEN)); }

pb::dict channelDict(const polyloc_channel_desc& d) {
  using namespace shm_dicts_impl;
  pb::dict c;
  c["name"] = channelName(d), c["kind"] = kindName(d.kind);
  c["direction"] = d.direction == POLYLOC_DIR_INPUT ? "input" : "output";
  c["count"] = d.count, c["width"] = d.width, c["height"] = d.height, c["sensor"] = d.sensor;
  c["slots"] = d.slot_count, c["payload_max"] = d.payload_max;
  return c;
}

pb::dict specDict(const shm::ChannelSpec& s) {
  using namespace shm_dicts_impl;
  pb::dict c;
  c["name"] = s.name, c["kind"] = kindName(s.kind), c["direction"] = s.direction == POLYLOC_DIR_INPUT ? "input" : "output";
  c["count"] = s.count, c["width"] = s.width, c["height"] = s.height, c["sensor"] = s.sensor, c["slots"] = s.slot_count;
  return c;
}

// Defaults: direction input for ranges, depth, odometry and command, output otherwise; slots 16,
// count width*height for depth, sensor -1, payload_max 0 (from the kind and sizes).
shm::ChannelSpec toSpec(const pb::handle& obj) {
  using namespace shm_dicts_impl;
  if (!pb::isinstance<pb::dict>(obj)) raise(PyExc_TypeError, "channels: expected dicts with name and kind");
  const pb::dict d = pb::reinterpret_borrow<pb::dict>(obj);
  static const char* known[] = {"name", "kind", "direction", "slots", "count", "width", "height", "sensor", "payload_max"};
  for (auto item : d) {
    const std::string key = pb::str(item.first);
    if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return key == k; }) == std::end(known))
      raise(PyExc_ValueError, "channel spec: unknown key '" + key + "' (name, kind, direction, slots, count, width, height, sensor, payload_max)");
  }
  if (!d.contains("name") || !d.contains("kind")) raise(PyExc_ValueError, "channel spec: needs 'name' and 'kind'");
  shm::ChannelSpec s;
  s.name = d["name"].cast<std::string>();
  s.kind = kindOf(d["kind"]);
  s.direction = s.kind <= POLYLOC_KIND_COMMAND ? POLYLOC_DIR_INPUT : POLYLOC_DIR_OUTPUT;  // kinds below 10 are inputs
  if (d.contains("direction")) {
    const std::string dir = d["direction"].cast<std::string>();
    if (dir != "input" && dir != "output") raise(PyExc_ValueError, "channel '" + s.name + "': direction '" + dir + "' (input or output)");
    s.direction = dir == "input" ? POLYLOC_DIR_INPUT : POLYLOC_DIR_OUTPUT;
  }
  auto u32 = [&](const char* key, uint32_t def) { return d.contains(key) ? d[key].cast<uint32_t>() : def; };
  s.slot_count = u32("slots", 16);
  s.width = u32("width", 0), s.height = u32("height", 0);
  s.count = u32("count", s.kind == POLYLOC_KIND_DEPTH ? s.width * s.height : 0);
  s.payload_max = u32("payload_max", 0);
  s.sensor = d.contains("sensor") ? d["sensor"].cast<int32_t>() : -1;
  return s;
}

// Every dict has frame, stamp_ns and publish_ns.
pb::dict frameDict(const shm::FrameInfo& f, const std::vector<uint8_t>& buf, const polyloc_channel_desc& c,
                   const std::vector<std::string>& inputs) {
  using namespace shm_dicts_impl;
  pb::dict d;
  d["frame"] = f.frame, d["publish_ns"] = f.publish_ns;
  const size_t n = buf.size();
  switch (c.kind) {
    case POLYLOC_KIND_RANGES: {
      const auto h = fixedPart<polyloc_ranges>(buf);
      const size_t off = offsetof(polyloc_ranges, ranges);
      const size_t count = std::min<size_t>(h.count, n > off ? (n - off) / sizeof(float) : 0);
      d["stamp_ns"] = h.stamp_ns;
      d["ranges"] = floats(buf.data() + off, {pb::ssize_t(count)});
      break;
    }
    case POLYLOC_KIND_DEPTH: {
      const auto h = fixedPart<polyloc_depth>(buf);
      const size_t off = offsetof(polyloc_depth, data), pixels = size_t(h.width) * h.height;
      d["stamp_ns"] = h.stamp_ns;
      const bool whole = n >= off + pixels * sizeof(float);
      d["depth"] = whole ? pb::object(floats(buf.data() + off, {pb::ssize_t(h.height), pb::ssize_t(h.width)})) : pb::none();
      d["amplitude"] = h.has_amplitude && n >= off + 2 * pixels * sizeof(float)
                           ? pb::object(floats(buf.data() + off + pixels * sizeof(float), {pb::ssize_t(h.height), pb::ssize_t(h.width)}))
                           : pb::none();
      break;
    }
    case POLYLOC_KIND_ODOMETRY: {
      const auto o = fixedPart<polyloc_odometry>(buf);
      d["stamp_ns"] = o.stamp_ns;
      d["pose"] = quaternionPose(o.x, o.y, o.z, o.qw, o.qx, o.qy, o.qz);
      d["twist"] = pb::make_tuple(o.vx, o.vy, o.wz);
      break;
    }
    case POLYLOC_KIND_COMMAND: {
      const auto c = fixedPart<polyloc_command>(buf);
      d["stamp_ns"] = c.stamp_ns;
      d["twist"] = pb::make_tuple(c.vx, c.vy, c.wz);
      d["nav_state"] = c.nav_state <= POLYLOC_NAV_FAILED ? kNavStates[c.nav_state] : "unknown";
      d["goal"] = c.goal;
      d["status"] = std::string(c.status, strnlen(c.status, sizeof c.status));
      break;
    }
    case POLYLOC_KIND_POSE: {
      const auto p = fixedPart<polyloc_pose>(buf);
      d["stamp_ns"] = p.stamp_ns;
      d["pose"] = quaternionPose(p.x, p.y, p.z, p.qw, p.qx, p.qy, p.qz);
      pb::array_t<double> cov({6, 6});
      std::memcpy(cov.mutable_data(), p.covariance, sizeof p.covariance);
      d["covariance"] = cov;
      // POLYLOC_POSE_* and MclStatus share their order.
      d["status"] = p.status <= POLYLOC_POSE_LOST ? toString(static_cast<MclStatus>(p.status)) : "unknown";
      d["ess"] = p.ess, d["particles"] = p.particles, d["updates"] = p.updates, d["latency_ns"] = p.latency_ns;
      const double* mo = p.map_odom;
      d["map_odom"] = quaternionPose(mo[0], mo[1], mo[2], mo[3], mo[4], mo[5], mo[6]);
      break;
    }
    case POLYLOC_KIND_VRS: {
      const auto v = fixedPart<polyloc_vrs>(buf);
      const size_t off = offsetof(polyloc_vrs, ranges);
      const size_t count = std::min<size_t>(v.count, n > off ? (n - off) / sizeof(float) : 0);
      d["stamp_ns"] = v.stamp_ns;
      d["angle_min"] = v.angle_min, d["angle_increment"] = v.angle_increment;
      d["range_min"] = v.range_min, d["range_max"] = v.range_max, d["enabled"] = v.enabled != 0;
      pb::array_t<float> angles(static_cast<pb::ssize_t>(count));
      for (size_t i = 0; i < count; ++i) angles.mutable_at(i) = v.angle_min + float(i) * v.angle_increment;
      d["angles"] = angles;
      d["ranges"] = floats(buf.data() + off, {pb::ssize_t(count)});
      break;
    }
    case POLYLOC_KIND_TRACKS: {
      const auto t = fixedPart<polyloc_tracks>(buf);
      const size_t held = n > offsetof(polyloc_tracks, tracks) ? (n - offsetof(polyloc_tracks, tracks)) / sizeof(polyloc_track) : 0;
      const auto k = static_cast<pb::ssize_t>(std::min<size_t>({t.count, POLYLOC_MAX_TRACKS, held}));
      pb::array_t<uint32_t> id(k);
      pb::array_t<uint8_t> status(k);
      pb::array_t<double> pos({k, pb::ssize_t{2}}), vel({k, pb::ssize_t{2}}), cov({k, pb::ssize_t{2}, pb::ssize_t{2}});
      for (pb::ssize_t i = 0; i < k; ++i) {
        const polyloc_track& s = t.tracks[i];
        id.mutable_at(i) = s.id, status.mutable_at(i) = static_cast<uint8_t>(s.status);
        pos.mutable_at(i, 0) = s.x, pos.mutable_at(i, 1) = s.y, vel.mutable_at(i, 0) = s.vx, vel.mutable_at(i, 1) = s.vy;
        for (int r = 0; r < 2; ++r)
          for (int q = 0; q < 2; ++q) cov.mutable_at(i, r, q) = s.covariance[2 * r + q];
      }
      d["stamp_ns"] = t.stamp_ns;
      d["id"] = id, d["status"] = status, d["position"] = pos, d["velocity"] = vel, d["position_cov"] = cov;
      break;
    }
    case POLYLOC_KIND_HEALTH: {
      const auto h = fixedPart<polyloc_health>(buf);
      d["stamp_ns"] = h.stamp_ns;
      d["cycles"] = h.cycles, d["poses"] = h.poses, d["vrs"] = h.vrs, d["tracks"] = h.tracks;
      d["cycle_p50_ms"] = h.cycle_p50_ms, d["cycle_p99_ms"] = h.cycle_p99_ms;
      d["flags"] = h.flags, d["silent"] = (h.flags & 1u) != 0, d["lost"] = (h.flags & 2u) != 0;
      d["searching"] = (h.flags & 8u) != 0;  // a global search is running
      pb::dict in;
      for (uint32_t i = 0; i < std::min(h.inputs, POLYLOC_MAX_INPUTS); ++i) {
        const polyloc_input_health& e = h.input[i];
        pb::dict x;
        x["taken"] = e.taken, x["rejected_nan"] = e.rejected_nan, x["rejected_size"] = e.rejected_size;
        x["rejected_stale"] = e.rejected_stale, x["rejected_future"] = e.rejected_future, x["overruns"] = e.overruns;
        x["last_stamp_ns"] = e.last_stamp_ns, x["silent"] = e.silent != 0, x["extrapolated"] = e.extrapolated;
        in[pb::str(i < inputs.size() ? inputs[i] : "input" + std::to_string(i))] = x;
      }
      d["inputs"] = in;
      break;
    }
    default:
      d["stamp_ns"] = f.stamp_ns;
      d["payload"] = pb::bytes(reinterpret_cast<const char*>(buf.data()), buf.size());
  }
  return d;
}

polyloc_odometry odometryPayload(int64_t stamp_ns, const pb::handle& odom_T_base, const std::array<double, 3>& twist) {
  using namespace shm_dicts_impl;
  polyloc_odometry o{};
  o.stamp_ns = stamp_ns;
  putPose(toPose(odom_T_base, "odom_T_base"), &o.x, &o.qw);
  o.vx = twist[0], o.vy = twist[1], o.wz = twist[2];
  return o;
}

polyloc_command commandPayload(int64_t stamp_ns, const std::array<double, 3>& twist, const std::string& nav_state,
                               uint32_t goal, const std::string& status) {
  using namespace shm_dicts_impl;
  polyloc_command c{};
  c.stamp_ns = stamp_ns;
  c.vx = twist[0], c.vy = twist[1], c.wz = twist[2];
  c.nav_state = 4;
  for (uint32_t k = 0; k < 4; ++k)
    if (nav_state == kNavStates[k]) c.nav_state = k;
  if (c.nav_state > POLYLOC_NAV_FAILED)
    raise(PyExc_ValueError, "write_command: nav_state '" + nav_state + "' (idle, driving, reached, failed)");
  if (std::string why = shm::commandProblem(c.vx, c.vy, c.wz, c.nav_state); !why.empty())
    raise(PyExc_ValueError, "write_command: " + why);
  c.goal = goal;
  std::strncpy(c.status, status.c_str(), sizeof c.status - 1);
  return c;
}

polyloc_pose posePayload(int64_t stamp_ns, const pb::handle& pose, const pb::handle& covariance, const std::string& status,
                         size_t particles, double ess, uint64_t updates, int64_t latency_ns, const pb::handle& map_odom) {
  using namespace shm_dicts_impl;
  polyloc_pose p{};
  p.stamp_ns = stamp_ns;
  putPose(toPose(pose, "pose"), &p.x, &p.qw);
  if (!covariance.is_none()) {
    const Eigen::Matrix<double, 6, 6> cov = toCovariance(covariance, "covariance");
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) p.covariance[r * 6 + c] = cov(r, c);
  }
  p.status = static_cast<uint32_t>(statusOf(status));
  p.particles = static_cast<uint32_t>(particles), p.ess = ess, p.updates = updates, p.latency_ns = latency_ns;
  putPose(map_odom.is_none() ? Pose() : toPose(map_odom, "map_odom"), p.map_odom, p.map_odom + 3);
  return p;
}

// As polylocd publishes them: confirmed first, then tentative, deleted ones (status 2) left out,
// at most POLYLOC_MAX_TRACKS. Without status: confirmed; without velocity: 0; without position_cov: identity.
polyloc_tracks tracksPayload(int64_t stamp_ns, const pb::dict& tracks) {
  using namespace shm_dicts_impl;
  if (!tracks.contains("id") || !tracks.contains("position")) raise(PyExc_ValueError, "tracks: needs id and position arrays");
  const auto id = pb::array_t<uint32_t, pb::array::c_style | pb::array::forcecast>::ensure(tracks["id"]);
  if (!id || id.ndim() != 1) raise(PyExc_ValueError, "tracks['id']: expected a 1-D array of ids");
  const pb::ssize_t k = id.size();
  const auto pos = doubleArray(tracks["position"], "tracks['position']", {k, 2});
  const auto vel = tracks.contains("velocity") ? std::optional(doubleArray(tracks["velocity"], "tracks['velocity']", {k, 2})) : std::nullopt;
  const auto cov = tracks.contains("position_cov") ? std::optional(doubleArray(tracks["position_cov"], "tracks['position_cov']", {k, 2, 2})) : std::nullopt;
  std::optional<U8Array> st;
  if (tracks.contains("status")) st = byteArray(tracks["status"], "tracks['status']", {k});
  polyloc_tracks p{};
  p.stamp_ns = stamp_ns;
  for (uint32_t wanted : {1u, 0u})
    for (pb::ssize_t i = 0; i < k && p.count < POLYLOC_MAX_TRACKS; ++i) {
      const uint32_t status = st ? std::min<uint8_t>(st->at(i), 2) : 1u;
      if (status != wanted) continue;
      polyloc_track& t = p.tracks[p.count++];
      t.id = id.at(i), t.status = status;
      t.x = pos.at(i, 0), t.y = pos.at(i, 1);
      if (vel) t.vx = vel->at(i, 0), t.vy = vel->at(i, 1);
      t.covariance[0] = t.covariance[3] = 1;
      if (cov)
        for (int r = 0; r < 2; ++r)
          for (int q = 0; q < 2; ++q) t.covariance[2 * r + q] = cov->at(i, r, q);
    }
  return p;
}

polyloc_health healthPayload(int64_t stamp_ns, const pb::dict& health, const std::vector<std::string>& names,
                             const std::string& segment) {
  using namespace shm_dicts_impl;
  polyloc_health h{};
  h.stamp_ns = stamp_ns;
  h.cycles = get<uint64_t>(health, "cycles", 0), h.poses = get<uint64_t>(health, "poses", 0);
  h.vrs = get<uint64_t>(health, "vrs", 0), h.tracks = get<uint64_t>(health, "tracks", 0);
  h.cycle_p50_ms = get<double>(health, "cycle_p50_ms", 0), h.cycle_p99_ms = get<double>(health, "cycle_p99_ms", 0);
  h.flags = get<uint32_t>(health, "flags", 0);
  h.inputs = static_cast<uint32_t>(std::min<size_t>(names.size(), POLYLOC_MAX_INPUTS));
  if (health.contains("inputs")) {
    for (auto item : health["inputs"].cast<pb::dict>()) {
      const std::string name = pb::str(item.first);
      const auto at = std::find(names.begin(), names.end(), name);
      if (at == names.end() || at - names.begin() >= POLYLOC_MAX_INPUTS)
        raise(PyExc_KeyError, "health inputs: '" + name + "' is not an input channel of " + segment);
      polyloc_input_health& e = h.input[at - names.begin()];
      const pb::dict x = item.second.cast<pb::dict>();
      e.taken = get<uint64_t>(x, "taken", 0), e.rejected_nan = get<uint64_t>(x, "rejected_nan", 0);
      e.rejected_size = get<uint64_t>(x, "rejected_size", 0), e.rejected_stale = get<uint64_t>(x, "rejected_stale", 0);
      e.rejected_future = get<uint64_t>(x, "rejected_future", 0), e.overruns = get<uint64_t>(x, "overruns", 0);
      e.last_stamp_ns = get<int64_t>(x, "last_stamp_ns", 0), e.silent = get<bool>(x, "silent", false);
      e.extrapolated = get<uint64_t>(x, "extrapolated", 0);
    }
  }
  return h;
}

}  // namespace polyloc::py
