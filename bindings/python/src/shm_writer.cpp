// polyloc.shm.Writer: one channel's writer role, a write_* per payload kind (shm_dicts.cpp fills
// the structs); frames are copied into the slot with the GIL released.
#include "shm_dicts.hpp"
#include "shm_segment.hpp"

#include "shm/channel.hpp"

#include <polyloc_shm.h>

#include <pybind11/stl.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace polyloc::py {

namespace shm_writer_impl {  // named, not anonymous: the module is compiled in batches (unity build)

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

}  // namespace shm_writer_impl

void bindShmWriter(pb::module_& m) {
  using namespace shm_writer_impl;
  pb::class_<PyWriter>(m, "Writer", R"(The writer of one channel (claims its writer role; released by close() or on deletion).

    w = Writer(seg, "scan/s300_front_left")
    w.write_ranges(stamp_ns, ranges)          # float32 array of the channel's beam count

One write_* per kind; a frame that does not fit the channel is a ValueError. write_bytes sends
any payload (for frames polylocd must reject). BusyError when a live process holds the role,
unless take_over.)")
      .def(pb::init([](SegmentPtr seg, const std::string& channel, bool take_over) {
  using namespace shm_writer_impl;
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
        w.writeStruct(odometryPayload(stamp_ns, pose, twist), stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("odom_T_base"), pb::arg("twist") = std::array<double, 3>{0, 0, 0},
           "Cumulative odometry odom_T_base (a Pose, (4, 4) or x, y, z, roll, pitch, yaw); twist (vx, vy, wz), informational.")
      .def("write_command", [](PyWriter& w, int64_t stamp_ns, std::array<double, 3> twist, const std::string& nav_state,
                               uint32_t goal, const std::string& status) {
        w.need(POLYLOC_KIND_COMMAND, "write_command");
        w.writeStruct(commandPayload(stamp_ns, twist, nav_state, goal, status), stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("twist"), pb::arg("nav_state") = "driving", pb::arg("goal") = 0,
           pb::arg("status") = "",
           "A velocity command for the base on cmd_vel: twist (vx, vy, wz) in base_link, the controller's state "
           "(idle, driving, reached, failed), goal number, a status line (cut at 63 bytes).")
      .def("write_pose", [](PyWriter& w, int64_t stamp_ns, const pb::handle& pose, const pb::handle& covariance,
                            const std::string& status, size_t particles, double ess, uint64_t updates, int64_t latency_ns,
                            const pb::handle& map_odom) {
        w.need(POLYLOC_KIND_POSE, "write_pose");
        w.writeStruct(posePayload(stamp_ns, pose, covariance, status, particles, ess, updates, latency_ns, map_odom), stamp_ns);
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
        w.writeStruct(tracksPayload(stamp_ns, tracks), stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("tracks"),
           "Tracks as PeopleTracker.tracks() gives them (id, status, position (K, 2), velocity, position_cov (K, 2, 2)); "
           "deleted ones are left out, confirmed first, at most 64.")
      .def("write_health", [](PyWriter& w, int64_t stamp_ns, const pb::dict& health) {
        w.need(POLYLOC_KIND_HEALTH, "write_health");
        std::vector<std::string> names;
        {
          std::shared_lock lock(w.seg->mutex);
          names = inputNames(*w.seg);
        }
        w.writeStruct(healthPayload(stamp_ns, health, names, w.seg->get().name()), stamp_ns);
      }, pb::arg("stamp_ns"), pb::arg("health"),
           "A health frame from a dict like Reader.next() gives (cycles, poses, vrs, tracks, cycle_p50_ms, cycle_p99_ms, "
           "flags, inputs: {input channel: {taken, rejected_*, overruns, last_stamp_ns, silent, extrapolated}}).");
}

}  // namespace polyloc::py
