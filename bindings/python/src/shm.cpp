// polyloc.shm: the shared-memory client (service/shm, docs/interface.md) over numpy arrays: attach
// to a polylocd instance's segment (or create one, for tests and simulations), write its input
// channels, read its outputs as dicts. Every frame of every kind can be written and read, so a
// Python program can stand in for either side. ShmError codes become Python exceptions that
// derive from the builtin a caller would catch (SegmentNotFoundError is a FileNotFoundError).
#include "common.hpp"

#include "pipeline/channels.hpp"
#include "pipeline/shm_payloads.hpp"
#include "shm/channel.hpp"
#include "shm/atomic.hpp"
#include "shm/segment.hpp"
#include "shm/validate.hpp"

#include <polyloc/configfile/polyloc_config.hpp>

#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <unistd.h>
#include <vector>

namespace polyloc::py {

namespace {

using shm::ShmError;
using Errc = ShmError::Errc;

// The exception classes of polyloc.shm (created in bindShm, alive as long as the module).
PyObject* exc_base = nullptr;        // ShmError(RuntimeError)
PyObject* exc_not_found = nullptr;   // SegmentNotFoundError(ShmError, FileNotFoundError)
PyObject* exc_abi = nullptr;         // AbiError(ShmError)
PyObject* exc_not_ready = nullptr;   // NotReadyError(ShmError)
PyObject* exc_busy = nullptr;        // BusyError(ShmError)
PyObject* exc_argument = nullptr;    // ShmValueError(ShmError, ValueError)

PyObject* newException(pb::module_& m, const char* name, const char* doc, std::vector<PyObject*> bases) {
  pb::tuple b(bases.size());
  for (size_t i = 0; i < bases.size(); ++i) b[i] = pb::reinterpret_borrow<pb::object>(bases[i]);
  const std::string full = std::string("polyloc.shm.") + name;
  PyObject* e = PyErr_NewExceptionWithDoc(full.c_str(), doc, b.ptr(), nullptr);
  if (!e) throw pb::error_already_set();
  m.attr(name) = pb::reinterpret_borrow<pb::object>(e);  // the module keeps a reference too
  return e;
}

PyObject* exceptionFor(Errc c) {
  switch (c) {
    case Errc::NotFound: return exc_not_found;
    case Errc::Abi: return exc_abi;
    case Errc::NotReady: return exc_not_ready;
    case Errc::Busy: return exc_busy;
    case Errc::Argument: return exc_argument;
    default: return exc_base;
  }
}

const char* kindName(uint32_t k) {
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

uint32_t kindOf(const pb::handle& v) {
  if (pb::isinstance<pb::int_>(v)) return v.cast<uint32_t>();
  const std::string s = v.cast<std::string>();
  for (uint32_t k : {POLYLOC_KIND_RANGES, POLYLOC_KIND_DEPTH, POLYLOC_KIND_ODOMETRY, POLYLOC_KIND_COMMAND, POLYLOC_KIND_POSE,
                     POLYLOC_KIND_VRS, POLYLOC_KIND_TRACKS, POLYLOC_KIND_HEALTH})
    if (s == kindName(k)) return k;
  raise(PyExc_ValueError, "channel kind '" + s + "': one of ranges, depth, odometry, command, pose, vrs, tracks, health");
}

const char* stateName(uint32_t s) {
  switch (s) {
    case POLYLOC_STATE_INITIALISING: return "initialising";
    case POLYLOC_STATE_READY: return "ready";
    case POLYLOC_STATE_STOPPED: return "stopped";
    default: return "unknown";
  }
}

std::string channelName(const polyloc_channel_desc& d) { return std::string(d.name, strnlen(d.name, POLYLOC_NAME_LEN)); }

pb::dict channelDict(const polyloc_channel_desc& d) {
  pb::dict c;
  c["name"] = channelName(d), c["kind"] = kindName(d.kind);
  c["direction"] = d.direction == POLYLOC_DIR_INPUT ? "input" : "output";
  c["count"] = d.count, c["width"] = d.width, c["height"] = d.height, c["sensor"] = d.sensor;
  c["slots"] = d.slot_count, c["payload_max"] = d.payload_max;
  return c;
}

pb::dict specDict(const shm::ChannelSpec& s) {
  pb::dict c;
  c["name"] = s.name, c["kind"] = kindName(s.kind), c["direction"] = s.direction == POLYLOC_DIR_INPUT ? "input" : "output";
  c["count"] = s.count, c["width"] = s.width, c["height"] = s.height, c["sensor"] = s.sensor, c["slots"] = s.slot_count;
  return c;
}

// A channel spec from a dict: name and kind required; direction (default: input for ranges,
// depth and odometry, output otherwise), slots (16), count, width, height, sensor (-1), payload_max (0).
shm::ChannelSpec toSpec(const pb::handle& obj) {
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

// One segment, shared by the Readers and Writers made on it. They keep a pointer to `seg`
// (shm::Reader/Writer follow a re-attach of that object), so it is only ever assigned, under
// the exclusive lock; every read or write holds the shared one.
struct PySegment {
  std::optional<shm::Segment> seg;
  std::shared_mutex mutex;
  bool owner = false;   // made by create(): the context manager stops and unlinks it
  bool closed = false;  // unlinked by __exit__ (the mapping stays: readers still read)

  shm::Segment& get() { return *seg; }
};
using SegmentPtr = std::shared_ptr<PySegment>;

int channelIndex(PySegment& s, const std::string& channel) {
  const int ch = s.get().find(channel);
  if (ch < 0) {
    std::string names;
    for (int i = 0; i < s.get().channelCount(); ++i) names += (i ? ", " : "") + channelName(s.get().channel(i));
    raise(PyExc_KeyError, "segment " + s.get().name() + " has no channel '" + channel + "' (it has " + names + ")");
  }
  return ch;
}

// The names of the input channels in channel order (health input[i] belongs to the i-th).
std::vector<std::string> inputNames(PySegment& s) {
  std::vector<std::string> out;
  for (int i = 0; i < s.get().channelCount(); ++i)
    if (s.get().channel(i).direction == POLYLOC_DIR_INPUT) out.push_back(channelName(s.get().channel(i)));
  return out;
}

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

Pose quaternionPose(double x, double y, double z, double qw, double qx, double qy, double qz) {
  const Eigen::Quaterniond q(qw, qx, qy, qz);  // a zero quaternion (a frame never filled in): no rotation
  return Pose(q.norm() > 0 ? q.normalized() : Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, z));
}

// A frame as read (buf: min(size, payload_max) bytes, untrusted: array lengths are bounded by
// what the bytes hold) into a dict. Every dict has frame, stamp_ns and publish_ns.
pb::dict decode(const shm::FrameInfo& f, const std::vector<uint8_t>& buf, const polyloc_channel_desc& c,
                const std::vector<std::string>& inputs) {
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
      static const char* states[] = {"idle", "driving", "reached", "failed"};
      d["stamp_ns"] = c.stamp_ns;
      d["twist"] = pb::make_tuple(c.vx, c.vy, c.wz);
      d["nav_state"] = c.nav_state <= POLYLOC_NAV_FAILED ? states[c.nav_state] : "unknown";
      d["goal"] = c.goal;
      d["status"] = std::string(c.status, strnlen(c.status, sizeof c.status));
      break;
    }
    case POLYLOC_KIND_POSE: {
      const auto p = fixedPart<polyloc_pose>(buf);
      d["stamp_ns"] = p.stamp_ns;
      d["pose"] = pipeline::posePose(p);
      pb::array_t<double> cov({6, 6});
      std::memcpy(cov.mutable_data(), p.covariance, sizeof p.covariance);
      d["covariance"] = cov;
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

struct PyWriter {
  SegmentPtr seg;
  std::unique_ptr<shm::Writer> w;
  std::mutex mutex;
  polyloc_channel_desc desc{};
  std::string name;

  shm::Writer& get() {
    if (!w) throw std::runtime_error("Writer of channel '" + name + "' is closed");  // C++: may run without the GIL
    return *w;
  }
  void need(uint32_t kind, const char* call) const {
    if (desc.kind != kind)
      raise(PyExc_ValueError, std::string(call) + ": channel '" + name + "' is a " + kindName(desc.kind) + " channel, not " +
                                  kindName(kind));
  }
  // Copies the parts into the next slot and publishes it (GIL released meanwhile).
  void write(const std::vector<std::pair<const void*, size_t>>& parts, int64_t stamp_ns) {
    size_t bytes = 0;
    for (const auto& p : parts) bytes += p.second;
    pb::gil_scoped_release nogil;
    std::shared_lock lock(seg->mutex);
    Guard g(mutex);
    shm::Writer& wr = get();
    if (bytes > wr.channel().payload_max)
      throw std::length_error("channel '" + name + "': a frame of " + std::to_string(bytes) + " bytes, at most " +
                              std::to_string(wr.channel().payload_max));
    uint8_t* p = wr.begin();
    for (const auto& part : parts) std::memcpy(p, part.first, part.second), p += part.second;
    wr.commit(static_cast<uint32_t>(bytes), stamp_ns);
  }
  template <class T> void writeStruct(const T& v, int64_t stamp_ns) { write({{&v, sizeof v}}, stamp_ns); }
};

struct PyReader {
  SegmentPtr seg;
  std::unique_ptr<shm::Reader> r;
  std::mutex mutex;
  polyloc_channel_desc desc{};

  template <class F> pb::object read(F&& f) {
    std::vector<uint8_t> buf;
    std::optional<shm::FrameInfo> info;
    std::vector<std::string> inputs;
    polyloc_channel_desc now{};
    {
      pb::gil_scoped_release nogil;
      std::shared_lock lock(seg->mutex);
      Guard g(mutex);
      info = f(*r, buf);
      now = r->channel();  // after a re-attach: the channel as it is in the new segment
      if (info && now.kind == POLYLOC_KIND_HEALTH) inputs = inputNames(*seg);
    }
    if (!info) return pb::none();
    return decode(*info, buf, now, inputs);
  }
};

MclStatus statusOf(const std::string& s) {
  for (auto v : {MclStatus::Initialising, MclStatus::Tracking, MclStatus::Uncertain, MclStatus::Lost})
    if (s == toString(v)) return v;
  raise(PyExc_ValueError, "status '" + s + "': one of initialising, tracking, uncertain, lost");
}

template <class T> T get(const pb::dict& d, const char* key, T def) { return d.contains(key) ? d[key].cast<T>() : def; }

}  // namespace

void bindShm(pb::module_& parent) {
  pb::module_ m = parent.def_submodule("_shm", R"(The shared-memory client: polylocd's segment, its input and output channels.

    seg = shm.Segment.attach("lab")                    # polylocd --instance lab
    pose = shm.Reader(seg, "pose", start="newest")
    odom = shm.Writer(seg, "odom")
    odom.write_odometry(stamp_ns, odom_T_base)
    if pose.wait(0.1): print(pose.next())              # dict: stamp_ns, pose, covariance, status, ...

docs/interface.md is the layout; docs/python.md has an example.)");

  exc_base = newException(m, "ShmError", "A shared-memory failure: the message names the segment and what was wrong.",
                          {PyExc_RuntimeError});
  exc_not_found = newException(m, "SegmentNotFoundError", "No segment of that name (is polylocd running for the instance?).",
                               {exc_base, PyExc_FileNotFoundError});
  exc_abi = newException(m, "AbiError", "The segment speaks another POLYLOC_SHM_ABI_VERSION (both versions in the message).",
                         {exc_base});
  exc_not_ready = newException(m, "NotReadyError", "The segment is being created (polylocd is starting): retry.", {exc_base});
  exc_busy = newException(m, "BusyError", "A live process holds the segment or the channel's writer role.", {exc_base});
  exc_argument = newException(m, "ShmValueError", "A bad instance name or channel spec.", {exc_base, PyExc_ValueError});
  pb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ShmError& e) {
      PyErr_SetString(exceptionFor(e.code()), e.what());
    }
  });
  m.attr("ABI_VERSION") = POLYLOC_SHM_ABI_VERSION;

  m.def("daemon_channels", [](const PolylocConfig& config, uint32_t slots) {
    pb::list out;
    for (const shm::ChannelSpec& s : pipeline::channelTable(config.rig, config.vrs, slots).specs) out.append(specDict(s));
    return out;
  }, pb::arg("config"), pb::arg("slots") = 16,
        "polylocd's channel table for a config (scan/<sensor>, depth/<camera>, odom, pose, vrs, tracks, health), as "
        "specs for Segment.create.");

  pb::class_<PySegment, SegmentPtr>(m, "Segment", R"(One polylocd instance's segment /dev/shm/polyloc.<instance>.

    seg = Segment.attach("lab")              # SegmentNotFoundError, AbiError, NotReadyError, ShmError
    seg.channels()                           # [{'name': 'scan/s300_front_left', 'kind': 'ranges', ...}, ...]
    if seg.stale(): seg.reattach()           # polylocd restarted or stopped; readers and writers follow

    with Segment.create("sim", [{"name": "pose", "kind": "pose"}, ...]) as seg:   # tests, simulations
        ...                                  # on exit: state stopped and the name unlinked)")
      .def_static("attach", [](const std::string& instance) {
        auto s = std::make_shared<PySegment>();
        {
          pb::gil_scoped_release nogil;
          s->seg = shm::Segment::attach(instance);
        }
        return s;
      }, pb::arg("instance"), "Maps an existing segment; checks magic, ABI version, sizes and state.")
      .def_static("create", [](const std::string& instance, const pb::iterable& channels, bool ready) {
        std::vector<shm::ChannelSpec> specs;
        for (auto c : channels) specs.push_back(toSpec(c));
        auto s = std::make_shared<PySegment>();
        s->owner = true;
        pb::gil_scoped_release nogil;
        s->seg = shm::Segment::create(instance, specs);
        if (ready) s->seg->ready();
        return s;
      }, pb::arg("instance"), pb::arg("channels"), pb::arg("ready") = true,
        R"(Creates (or replaces: generation + 1) the segment with these channels, owned by this process.

channels: dicts with name and kind ('ranges', 'depth', 'odometry', 'pose', 'vrs', 'tracks', 'health'),
optional direction ('input'/'output'; default by kind), slots (16), count (beams, VRS segments),
width and height (depth), sensor (rig index, -1), payload_max; or daemon_channels(config).
ready=False leaves it initialising (clients cannot attach) until ready().)")
      .def_static("unlink", [](const std::string& instance) {
        pb::gil_scoped_release nogil;
        shm::Segment::unlink(instance);
      }, pb::arg("instance"), "Removes the name (mapped segments stay valid).")
      .def_property_readonly("instance", [](PySegment& s) { return s.get().instance(); })
      .def_property_readonly("name", [](PySegment& s) { return s.get().name(); }, "/polyloc.<instance>")
      .def_property_readonly("generation", [](PySegment& s) { return s.get().generation(); }, "as attached")
      .def_property_readonly("state", [](PySegment& s) {
        return stateName(shm::atomic::loadAcquire(&s.get().header().state));
      }, "'initialising', 'ready' or 'stopped' (now)")
      .def_property_readonly("owner_pid", [](PySegment& s) { return s.get().header().owner_pid; })
      .def_property_readonly("created_ns", [](PySegment& s) { return s.get().header().created_ns; })
      .def_property_readonly("size", [](PySegment& s) { return s.get().size(); }, "bytes")
      .def_property_readonly("owner", [](PySegment& s) { return s.owner; }, "made by create() in this process")
      .def("stale", [](PySegment& s) {
        pb::gil_scoped_release nogil;
        std::shared_lock lock(s.mutex);
        return s.get().stale();
      }, "True when polylocd restarted (another generation), stopped or died: reattach(). A few system calls.")
      .def("reattach", [](PySegment& s) {
        pb::gil_scoped_release nogil;
        std::unique_lock lock(s.mutex);
        s.seg = shm::Segment::attach(s.get().instance());
        s.owner = false;
      }, "Attaches again by instance name, in place: Readers and Writers on this Segment follow on their next call.")
      .def("ready", [](PySegment& s) { s.get().ready(); }, "State ready (the owner).")
      .def("stop", [](PySegment& s) { s.get().stop(); }, "State stopped (the owner): clients see it stale.")
      .def("channels", [](PySegment& s) {
        std::shared_lock lock(s.mutex);
        pb::list out;
        for (int i = 0; i < s.get().channelCount(); ++i) out.append(channelDict(s.get().channel(i)));
        return out;
      }, "The channel table: dicts of name, kind, direction, count, width, height, sensor, slots, payload_max.")
      .def("find", [](PySegment& s, const std::string& name) { return s.get().find(name); }, pb::arg("channel"),
           "Index of a channel, or -1.")
      .def("__contains__", [](PySegment& s, const std::string& name) { return s.get().find(name) >= 0; })
      .def("__enter__", [](SegmentPtr s) { return s; })
      .def("__exit__", [](PySegment& s, pb::args) {
        if (s.owner && !s.closed) {
          s.get().stop();
          shm::Segment::unlink(s.get().instance());
          s.closed = true;
        }
        return false;
      }, "For a segment made by create(): state stopped and the name unlinked.")
      .def("__repr__", [](PySegment& s) {
        return "<polyloc.shm.Segment " + s.get().name() + " generation " + std::to_string(s.get().generation()) + ", " +
               std::to_string(s.get().channelCount()) + " channels>";
      });

  pb::class_<PyWriter>(m, "Writer", R"(The writer of one channel (claims its writer role; released by close() or on deletion).

    w = Writer(seg, "scan/s300_front_left")
    w.write_ranges(stamp_ns, ranges)          # float32 array of the channel's beam count

One write_* per kind; a frame that does not fit the channel is a ValueError. write_bytes sends
any payload (for frames polylocd must reject). BusyError when a live process holds the role,
unless take_over.)")
      .def(pb::init([](SegmentPtr seg, const std::string& channel, bool take_over) {
             auto w = std::make_unique<PyWriter>();
             w->seg = seg;
             w->name = channel;
             const int ch = channelIndex(*seg, channel);
             pb::gil_scoped_release nogil;
             std::shared_lock lock(seg->mutex);
             w->w = std::make_unique<shm::Writer>(seg->get(), ch, take_over);
             w->desc = w->w->channel();
             return w;
           }),
           pb::arg("segment"), pb::arg("channel"), pb::arg("take_over") = false)
      .def_property_readonly("channel", [](PyWriter& w) { return channelDict(w.desc); })
      .def_property_readonly("written", [](PyWriter& w) {
        std::shared_lock lock(w.seg->mutex);
        return w.get().written();
      }, "frames committed on the channel")
      .def("close", [](PyWriter& w) {
        pb::gil_scoped_release nogil;
        std::shared_lock lock(w.seg->mutex);
        Guard g(w.mutex);
        w.w.reset();
      }, "Releases the writer role.")
      .def("__enter__", [](pb::object self) { return self; })
      .def("__exit__", [](PyWriter& w, pb::args) {
        std::shared_lock lock(w.seg->mutex);
        w.w.reset();
        return false;
      })
      .def("write_bytes", [](PyWriter& w, int64_t stamp_ns, const pb::bytes& payload) {
        const std::string_view v = payload;
        w.write({{v.data(), v.size()}}, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("payload"), "A raw payload (any bytes up to payload_max).")
      .def("write_ranges", [](PyWriter& w, int64_t stamp_ns, const pb::handle& ranges) {
        w.need(POLYLOC_KIND_RANGES, "write_ranges");
        const F32Array r = w.desc.count ? rangesArray(ranges, "ranges", w.desc.count) : floatArray(ranges, "ranges", {-1});
        const polyloc_ranges h{stamp_ns, static_cast<uint32_t>(r.size()), 0};
        w.write({{&h, offsetof(polyloc_ranges, ranges)}, {r.data(), size_t(r.size()) * sizeof(float)}}, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("ranges"), "A scan: ranges (B,) in the rig's beam order; NaN/inf: no return.")
      .def("write_depth", [](PyWriter& w, int64_t stamp_ns, const pb::handle& depth, const pb::handle& amplitude) {
        w.need(POLYLOC_KIND_DEPTH, "write_depth");
        const std::vector<pb::ssize_t> shape{pb::ssize_t(w.desc.height), pb::ssize_t(w.desc.width)};
        const F32Array dep = floatArray(depth, "depth", shape);
        std::optional<F32Array> amp;
        if (!amplitude.is_none()) amp = floatArray(amplitude, "amplitude", shape);
        const polyloc_depth h{stamp_ns, w.desc.width, w.desc.height, amp ? 1u : 0u, 0};
        const size_t bytes = size_t(dep.size()) * sizeof(float);
        std::vector<std::pair<const void*, size_t>> parts{{&h, offsetof(polyloc_depth, data)}, {dep.data(), bytes}};
        if (amp) parts.push_back({amp->data(), bytes});
        w.write(parts, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("depth"), pb::arg("amplitude") = pb::none(),
           "A depth frame: depth (H, W) in metres along the optical axis (not along the pixel rays), amplitude (H, W) or None.")
      .def("write_odometry", [](PyWriter& w, int64_t stamp_ns, const pb::handle& pose, std::array<double, 3> twist) {
        w.need(POLYLOC_KIND_ODOMETRY, "write_odometry");
        polyloc_odometry o = pipeline::odometryPayload(stamp_ns, toPose(pose, "odom_T_base"));
        o.vx = twist[0], o.vy = twist[1], o.wz = twist[2];
        w.writeStruct(o, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("odom_T_base"), pb::arg("twist") = std::array<double, 3>{0, 0, 0},
           "Cumulative odometry odom_T_base (a Pose, (4, 4) or x, y, z, roll, pitch, yaw); twist (vx, vy, wz), informational.")
      .def("write_command", [](PyWriter& w, int64_t stamp_ns, std::array<double, 3> twist, const std::string& nav_state,
                               uint32_t goal, const std::string& status) {
        w.need(POLYLOC_KIND_COMMAND, "write_command");
        static const char* states[] = {"idle", "driving", "reached", "failed"};
        polyloc_command c{};
        c.stamp_ns = stamp_ns;
        c.vx = twist[0], c.vy = twist[1], c.wz = twist[2];
        c.nav_state = 4;
        for (uint32_t k = 0; k < 4; ++k)
          if (nav_state == states[k]) c.nav_state = k;
        if (c.nav_state > POLYLOC_NAV_FAILED)
          raise(PyExc_ValueError, "write_command: nav_state '" + nav_state + "' (idle, driving, reached, failed)");
        if (std::string why = shm::commandProblem(c.vx, c.vy, c.wz, c.nav_state); !why.empty())
          raise(PyExc_ValueError, "write_command: " + why);
        c.goal = goal;
        std::strncpy(c.status, status.c_str(), sizeof c.status - 1);
        w.writeStruct(c, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("twist"), pb::arg("nav_state") = "driving", pb::arg("goal") = 0,
           pb::arg("status") = "",
           "A velocity command for the base on cmd_vel: twist (vx, vy, wz) in base_link, the controller's state "
           "(idle, driving, reached, failed), goal number, a status line (cut at 63 bytes).")
      .def("write_pose", [](PyWriter& w, int64_t stamp_ns, const pb::handle& pose, const pb::handle& covariance,
                            const std::string& status, size_t particles, double ess, uint64_t updates, int64_t latency_ns,
                            const pb::handle& map_odom) {
        w.need(POLYLOC_KIND_POSE, "write_pose");
        MclEstimate e;
        e.stamp_ns = stamp_ns, e.pose = toPose(pose, "pose");
        if (!covariance.is_none()) e.covariance = toCovariance(covariance, "covariance");
        e.status = statusOf(status), e.particles = particles, e.ess = ess, e.updates = updates;
        const Pose mo = map_odom.is_none() ? Pose() : toPose(map_odom, "map_odom");
        w.writeStruct(pipeline::posePayload(e, mo, latency_ns), stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("pose"), pb::arg("covariance") = pb::none(), pb::arg("status") = "tracking",
           pb::arg("particles") = 0, pb::arg("ess") = 0.0, pb::arg("updates") = 0, pb::arg("latency_ns") = 0,
           pb::arg("map_odom") = pb::none(), "A pose frame as polylocd publishes it (map_T_base; covariance (6, 6)).")
      .def("write_vrs", [](PyWriter& w, int64_t stamp_ns, const pb::handle& ranges, float angle_min, float angle_increment,
                           float range_min, float range_max, bool enabled) {
        w.need(POLYLOC_KIND_VRS, "write_vrs");
        const F32Array r = w.desc.count ? rangesArray(ranges, "ranges", w.desc.count) : floatArray(ranges, "ranges", {-1});
        polyloc_vrs h{};
        h.stamp_ns = stamp_ns, h.angle_min = angle_min, h.angle_increment = angle_increment;
        h.range_min = range_min, h.range_max = range_max, h.count = uint32_t(r.size()), h.enabled = enabled;
        w.write({{&h, offsetof(polyloc_vrs, ranges)}, {r.data(), size_t(r.size()) * sizeof(float)}}, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("ranges"), pb::arg("angle_min"), pb::arg("angle_increment"), pb::arg("range_min") = 0.f,
           pb::arg("range_max") = 8.f, pb::arg("enabled") = true,
           "A virtual range scan: ranges (S,), the first segment's centre at angle_min (base_link, like LaserScan).")
      .def("write_tracks", [](PyWriter& w, int64_t stamp_ns, const pb::dict& tracks) {
        w.need(POLYLOC_KIND_TRACKS, "write_tracks");
        Tracks t;
        t.stamp_ns = stamp_ns;
        if (!tracks.contains("id") || !tracks.contains("position")) raise(PyExc_ValueError, "tracks: needs id and position arrays");
        const auto id = pb::array_t<uint32_t, pb::array::c_style | pb::array::forcecast>::ensure(tracks["id"]);
        if (!id || id.ndim() != 1) raise(PyExc_ValueError, "tracks['id']: expected a 1-D array of ids");
        const pb::ssize_t k = id.size();
        const auto pos = doubleArray(tracks["position"], "tracks['position']", {k, 2});
        const auto vel = tracks.contains("velocity") ? std::optional(doubleArray(tracks["velocity"], "tracks['velocity']", {k, 2})) : std::nullopt;
        const auto cov = tracks.contains("position_cov") ? std::optional(doubleArray(tracks["position_cov"], "tracks['position_cov']", {k, 2, 2})) : std::nullopt;
        std::optional<U8Array> st;
        if (tracks.contains("status")) st = byteArray(tracks["status"], "tracks['status']", {k});
        for (pb::ssize_t i = 0; i < k; ++i) {
          TrackState s;
          s.id = id.at(i), s.status = st ? static_cast<TrackStatus>(std::min<uint8_t>(st->at(i), 2)) : TrackStatus::Confirmed;
          s.position = {pos.at(i, 0), pos.at(i, 1)};
          if (vel) s.velocity = {vel->at(i, 0), vel->at(i, 1)};
          if (cov) s.position_cov << cov->at(i, 0, 0), cov->at(i, 0, 1), cov->at(i, 1, 0), cov->at(i, 1, 1);
          t.items.push_back(s);
        }
        w.writeStruct(pipeline::tracksPayload(stamp_ns, t), stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("tracks"),
           "Tracks as PeopleTracker.tracks() gives them (id, status, position (K, 2), velocity, position_cov (K, 2, 2)); "
           "deleted ones are left out, confirmed first, at most 64.")
      .def("write_health", [](PyWriter& w, int64_t stamp_ns, const pb::dict& health) {
        w.need(POLYLOC_KIND_HEALTH, "write_health");
        polyloc_health h{};
        h.stamp_ns = stamp_ns;
        h.cycles = get<uint64_t>(health, "cycles", 0), h.poses = get<uint64_t>(health, "poses", 0);
        h.vrs = get<uint64_t>(health, "vrs", 0), h.tracks = get<uint64_t>(health, "tracks", 0);
        h.cycle_p50_ms = get<double>(health, "cycle_p50_ms", 0), h.cycle_p99_ms = get<double>(health, "cycle_p99_ms", 0);
        h.flags = get<uint32_t>(health, "flags", 0);
        std::vector<std::string> names;
        {
          std::shared_lock lock(w.seg->mutex);
          names = inputNames(*w.seg);
        }
        h.inputs = static_cast<uint32_t>(std::min<size_t>(names.size(), POLYLOC_MAX_INPUTS));
        if (health.contains("inputs")) {
          for (auto item : health["inputs"].cast<pb::dict>()) {
            const std::string name = pb::str(item.first);
            const auto at = std::find(names.begin(), names.end(), name);
            if (at == names.end() || at - names.begin() >= POLYLOC_MAX_INPUTS)
              raise(PyExc_KeyError, "health inputs: '" + name + "' is not an input channel of " + w.seg->get().name());
            polyloc_input_health& e = h.input[at - names.begin()];
            const pb::dict x = item.second.cast<pb::dict>();
            e.taken = get<uint64_t>(x, "taken", 0), e.rejected_nan = get<uint64_t>(x, "rejected_nan", 0);
            e.rejected_size = get<uint64_t>(x, "rejected_size", 0), e.rejected_stale = get<uint64_t>(x, "rejected_stale", 0);
            e.rejected_future = get<uint64_t>(x, "rejected_future", 0), e.overruns = get<uint64_t>(x, "overruns", 0);
            e.last_stamp_ns = get<int64_t>(x, "last_stamp_ns", 0), e.silent = get<bool>(x, "silent", false);
            e.extrapolated = get<uint64_t>(x, "extrapolated", 0);
          }
        }
        w.writeStruct(h, stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("health"),
           "A health frame from a dict like Reader.next() gives (cycles, poses, vrs, tracks, cycle_p50_ms, cycle_p99_ms, "
           "flags, inputs: {input channel: {taken, rejected_*, overruns, last_stamp_ns, silent, extrapolated}}).");

  pb::class_<PyReader>(m, "Reader", R"(A reader of one channel, at its own pace: it never disturbs the writer or other readers.

    r = Reader(seg, "pose", start="next")    # "next": frames after now; "newest": the last one too; "oldest": the ring
    while r.wait(0.1):                       # seconds; the GIL is released meanwhile
        frame = r.next()                     # a dict, or None when nothing is new

A reader that falls behind by more than the ring's slots skips to the newest frame and counts
the frames lost in overruns.)")
      .def(pb::init([](SegmentPtr seg, const std::string& channel, const std::string& start) {
             shm::Reader::Start s = shm::Reader::Start::Next;
             if (start == "newest") s = shm::Reader::Start::Newest;
             else if (start == "oldest") s = shm::Reader::Start::Oldest;
             else if (start != "next") raise(PyExc_ValueError, "start '" + start + "': next, newest or oldest");
             auto r = std::make_unique<PyReader>();
             r->seg = seg;
             const int ch = channelIndex(*seg, channel);
             std::shared_lock lock(seg->mutex);
             r->r = std::make_unique<shm::Reader>(seg->get(), ch, s);
             r->desc = r->r->channel();
             return r;
           }),
           pb::arg("segment"), pb::arg("channel"), pb::arg("start") = "next")
      .def_property_readonly("channel", [](PyReader& r) { return channelDict(r.desc); })
      .def("next", [](PyReader& r) {
        return r.read([](shm::Reader& rd, std::vector<uint8_t>& b) { return rd.next(b); });
      }, "The oldest unread frame as a dict, or None. After an overrun: the newest (and overruns grows).")
      .def("newest", [](PyReader& r) {
        return r.read([](shm::Reader& rd, std::vector<uint8_t>& b) { return rd.newest(b); });
      }, "The newest frame (skipping older unread ones, not an overrun), or None if none was ever published.")
      .def("drain", [](PyReader& r) {
        pb::list out;
        for (;;) {
          pb::object f = r.read([](shm::Reader& rd, std::vector<uint8_t>& b) { return rd.next(b); });
          if (f.is_none()) return out;
          out.append(f);
        }
      }, "Every unread frame, oldest first (a list of dicts).")
      .def("wait", [](PyReader& r, double timeout_s, double spin_s) {
        const int64_t timeout = timeout_s < 0 ? -1 : static_cast<int64_t>(timeout_s * 1e9);
        const auto spin = static_cast<int64_t>(std::max(0.0, spin_s) * 1e9);
        pb::gil_scoped_release nogil;
        std::shared_lock lock(r.seg->mutex);
        Guard g(r.mutex);
        return r.r->wait(timeout, spin);
      }, pb::arg("timeout_s"), pb::arg("spin_s") = 0.0,
           "Blocks (GIL released) until an unread frame is there or timeout_s passed (< 0: no limit, 0: poll); True when one is.")
      .def_property_readonly("available", [](PyReader& r) {
        pb::gil_scoped_release nogil;
        std::shared_lock lock(r.seg->mutex);
        Guard g(r.mutex);
        return r.r->available();
      }, "published frames not yet read (at most the ring's slots)")
      .def_property_readonly("overruns", [](PyReader& r) {
        pb::gil_scoped_release nogil;
        Guard g(r.mutex);
        return r.r->overruns();
      }, "frames lost because the writer lapped this reader")
      .def_property_readonly("torn", [](PyReader& r) {
        pb::gil_scoped_release nogil;
        Guard g(r.mutex);
        return r.r->torn();
      }, "reads retried because the writer overwrote the slot meanwhile");
}

}  // namespace polyloc::py
