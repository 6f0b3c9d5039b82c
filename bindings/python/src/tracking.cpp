// People tracking: motion detection on the level scanners, clusters, Kalman tracks (docs/tracking.md).
#include "common.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/tracking/config_yaml.hpp>
#include <polyloc/tracking/people_tracker.hpp>

#include <pybind11/stl.h>

#include <memory>
#include <mutex>

namespace polyloc::py {

namespace tracking_impl {  // named, not anonymous: the module is compiled in batches (unity build)

struct PyTracker {
  std::unique_ptr<PeopleTracker> tracker;
  std::mutex mutex;
};

// Tracks as arrays: id, status (0 tentative, 1 confirmed, 2 deleted), position, velocity,
// position covariance, hits.
pb::dict trackArrays(const Tracks& t) {
  const auto n = static_cast<pb::ssize_t>(t.items.size());
  pb::array_t<uint32_t> id(n), hits(n);
  pb::array_t<uint8_t> status(n);
  pb::array_t<double> pos({n, pb::ssize_t{2}}), vel({n, pb::ssize_t{2}}), cov({n, pb::ssize_t{2}, pb::ssize_t{2}});
  for (pb::ssize_t i = 0; i < n; ++i) {
    const TrackState& s = t.items[i];
    id.mutable_at(i) = s.id, hits.mutable_at(i) = s.hits, status.mutable_at(i) = static_cast<uint8_t>(s.status);
    for (int k = 0; k < 2; ++k) {
      pos.mutable_at(i, k) = s.position[k], vel.mutable_at(i, k) = s.velocity[k];
      for (int l = 0; l < 2; ++l) cov.mutable_at(i, k, l) = s.position_cov(k, l);
    }
  }
  pb::dict d;
  d["stamp_ns"] = t.stamp_ns, d["id"] = id, d["status"] = status, d["position"] = pos, d["velocity"] = vel;
  d["position_cov"] = cov, d["hits"] = hits;
  return d;
}

}  // namespace tracking_impl

void bindTracking(pb::module_& m) {
  using namespace tracking_impl;
  pb::class_<TrackingConfig>(m, "TrackingConfig", "People tracking settings (the tracking: section; docs/tracking.md).")
      .def(pb::init<>())
      .def_readwrite("sensors", &TrackingConfig::sensors, "level planar scanners by name; empty: all of them")
      .def_readwrite("sync_tolerance", &TrackingConfig::sync_tolerance, "s")
      .def_static("from_yaml", [](const std::string& text, const Rig* rig) {
        return parseTrackingConfig(ConfigMap::parse(text, "<tracking>"), rig);
      }, pb::arg("text"), pb::arg("rig") = nullptr, "From the YAML of a `tracking:` section (sensor names checked against rig).");

  pb::list status_names;
  for (auto s : {TrackStatus::Tentative, TrackStatus::Confirmed, TrackStatus::Deleted}) status_names.append(trackStatusName(s));
  m.attr("TRACK_STATUS_NAMES") = status_names;

  pb::class_<PyTracker>(m, "PeopleTracker", R"(Moving people from the free space of consecutive scans, followed with Kalman filters.

    people = PeopleTracker(cfg.rig, cfg.tracking)
    people.add_scan(sensor, stamp_ns, map_T_sensor, ranges)   # -> 'ok', 'wrong_size', ...
    people.tracks()    # dict of arrays: id, status (TRACK_STATUS_NAMES), position (K, 2), ...)")
      .def(pb::init([](const Rig& rig, const TrackingConfig& config) {
             auto p = std::make_unique<PyTracker>();
             p->tracker = std::make_unique<PeopleTracker>(rig, config);
             return p;
           }),
           pb::arg("rig"), pb::arg("config") = TrackingConfig{})
      .def("add_scan", [](PyTracker& t, size_t sensor, int64_t stamp, const pb::handle& pose, const pb::handle& ranges) {
        const Pose p = toPose(pose, "map_T_sensor");
        const F32Array r = floatArray(ranges, "ranges", {-1});
        pb::gil_scoped_release nogil;
        Guard g(t.mutex);
        return std::string(scanCheckName(
            t.tracker->addScan(sensor, stamp, p, std::span<const float>(r.data(), static_cast<size_t>(r.size())))));
      }, pb::arg("sensor"), pb::arg("stamp_ns"), pb::arg("map_T_sensor"), pb::arg("ranges"),
           "One scan of rig sensor `sensor`; returns what became of it (ok also for sensors tracking does not use).")
      .def("flush", [](PyTracker& t) {
        pb::gil_scoped_release nogil;
        Guard g(t.mutex);
        t.tracker->flush();
      }, "Cluster the pending scans and update the tracks now.")
      .def("tracks", [](PyTracker& t) {
        Guard g(t.mutex);
        return trackArrays(t.tracker->tracks());
      })
      .def_property_readonly("sensors", [](PyTracker& t) { return t.tracker->sensors(); }, "rig indices used")
      .def_property_readonly("counters", [](PyTracker& t) {
        Guard g(t.mutex);
        const TrackingCounters& c = t.tracker->counters();
        pb::dict d;
        d["scans"] = c.scans, d["rejected"] = c.rejected, d["ignored"] = c.ignored, d["steps"] = c.steps;
        d["detections"] = c.detections;
        return d;
      });
}

}  // namespace polyloc::py
