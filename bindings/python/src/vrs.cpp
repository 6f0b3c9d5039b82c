// Virtual range scans: every sensor of the rig fused into one 2D polar scan with the 3D
// obstacles, obstacle memory and danger zones (docs/vrs.md).
#include "common.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/vrs/config_yaml.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

#include <memory>
#include <mutex>

namespace polyloc::py {

namespace vrs_impl {  // named, not anonymous: the module is compiled in batches (unity build)

struct PyVrs {
  std::shared_ptr<const Mesh> map;  // danger-zone labels; the scanner keeps a pointer
  std::unique_ptr<VirtualRangeScanner> vrs;
  size_t sensors = 0;
  std::mutex mutex;
};

template <class T>
pb::array_t<T> scanView(pb::object self, const std::vector<T> VirtualScan::*field) {
  const std::vector<T>& v = self.cast<const VirtualScan&>().*field;
  return view<T>(v.data(), {static_cast<pb::ssize_t>(v.size())}, self);
}

}  // namespace vrs_impl

void bindVrs(pb::module_& m) {
  using namespace vrs_impl;
  pb::class_<VrsConfig>(m, "VrsConfig", "Virtual range scan settings (the vrs: section; docs/vrs.md). Angles in radians.")
      .def(pb::init<>())
      .def_readwrite("angle_min", &VrsConfig::angle_min)
      .def_readwrite("angle_max", &VrsConfig::angle_max)
      .def_readwrite("resolution", &VrsConfig::resolution, "segment width, rad")
      .def_readwrite("range_max", &VrsConfig::range_max)
      .def_readwrite("floor_clearance", &VrsConfig::floor_clearance)
      .def_readwrite("robot_height", &VrsConfig::robot_height)
      .def_readwrite("max_age", &VrsConfig::max_age)
      .def_readwrite("danger_labels", &VrsConfig::danger_labels)
      .def_property("memory_enabled", [](const VrsConfig& c) { return c.memory.enabled; },
                    [](VrsConfig& c, bool v) { c.memory.enabled = v; })
      .def_static("from_yaml", [](const std::string& text, double robot_height) {
        return parseVrsConfig(ConfigMap::parse(text, "<vrs>"), robot_height);
      }, pb::arg("text"), pb::arg("robot_height") = 1.2, "From the YAML of a `vrs:` section (degrees there).");

  pb::class_<VirtualScan>(m, "VirtualScan", "A VRS in base_link, LaserScan-like: ranges[i] covers one segment (+inf: nothing).")
      .def_readonly("stamp_ns", &VirtualScan::stamp_ns)
      .def_readonly("map_T_base", &VirtualScan::map_T_base)
      .def_readonly("angle_min", &VirtualScan::angle_min)
      .def_readonly("angle_increment", &VirtualScan::angle_increment)
      .def_readonly("range_min", &VirtualScan::range_min)
      .def_readonly("range_max", &VirtualScan::range_max)
      .def_property_readonly("ranges", [](pb::object s) { return scanView(s, &VirtualScan::ranges); }, "(S,) float32 nearest obstacle")
      .def_property_readonly("source", [](pb::object s) { return scanView(s, &VirtualScan::source); },
                             "(S,) uint8 bits: 1 direct, 2 memory, 4 danger zone")
      .def_property_readonly("ranges_max", [](pb::object s) { return scanView(s, &VirtualScan::ranges_max); },
                             "(S,) float32 farthest direct return (the localisation variant)")
      .def_property_readonly("angles", [](const VirtualScan& s) {
        pb::array_t<float> a(static_cast<pb::ssize_t>(s.size()));
        for (size_t i = 0; i < s.size(); ++i) a.mutable_at(i) = s.angleOf(i);
        return a;
      }, "(S,) float32 segment centre angles");

  pb::class_<PyVrs>(m, "VirtualRangeScanner", R"(Fuses the rig's frames into virtual range scans.

    vrs = VirtualRangeScanner(cfg.rig, cfg.robot, cfg.vrs, map=mesh)
    vrs.add_frame(sensor, stamp_ns, map_T_base, ranges)     # any order, any rate
    scan = vrs.update(stamp_ns, map_T_base))")
      .def(pb::init([](const Rig& rig, const RobotSpec& robot, const VrsConfig& config, std::shared_ptr<Mesh> map) {
             auto p = std::make_unique<PyVrs>();
             p->map = map;
             p->sensors = rig.size();
             p->vrs = std::make_unique<VirtualRangeScanner>(rig, robot, config, map.get());
             return p;
           }),
           pb::arg("rig"), pb::arg("robot"), pb::arg("config") = VrsConfig{}, pb::arg("map") = nullptr)
      .def("add_frame", [](PyVrs& v, size_t sensor, int64_t stamp, const pb::handle& pose, const pb::handle& ranges) {
        const Pose p = toPose(pose, "map_T_base");
        const F32Array r = floatArray(ranges, "ranges", {-1});
        pb::gil_scoped_release nogil;
        Guard g(v.mutex);
        return v.vrs->addFrame(sensor, stamp, p, std::span<const float>(r.data(), static_cast<size_t>(r.size())));
      }, pb::arg("sensor"), pb::arg("stamp_ns"), pb::arg("map_T_base"), pb::arg("ranges"),
           "One frame in beam order. False (and counted) for an unknown sensor, a wrong size or a bad pose.")
      .def("add_points", [](PyVrs& v, size_t sensor, int64_t stamp, const pb::handle& pose, const pb::handle& points) {
        const Pose p = toPose(pose, "map_T_base");
        const F32Array a = floatArray(points, "points", {-1, 3});
        std::vector<Eigen::Vector3f> pts(static_cast<size_t>(a.shape(0)));
        for (size_t i = 0; i < pts.size(); ++i) pts[i] = Eigen::Vector3f(a.data()[3 * i], a.data()[3 * i + 1], a.data()[3 * i + 2]);
        pb::gil_scoped_release nogil;
        Guard g(v.mutex);
        return v.vrs->addPoints(sensor, stamp, p, pts);
      }, pb::arg("sensor"), pb::arg("stamp_ns"), pb::arg("map_T_base"), pb::arg("points"),
           "Points (N, 3) already in base_link (DepthResult.points, lidar).")
      .def("set_moving_objects", [](PyVrs& v, const pb::handle& positions, const pb::handle& velocities, int64_t stamp) {
        const F64Array p = doubleArray(positions, "positions", {-1, 2});
        std::vector<MovingObject> objs(static_cast<size_t>(p.shape(0)));
        F64Array vel;
        if (!velocities.is_none()) vel = doubleArray(velocities, "velocities", {p.shape(0), 2});
        for (size_t i = 0; i < objs.size(); ++i) {
          objs[i].position = {p.data()[2 * i], p.data()[2 * i + 1]};
          if (!velocities.is_none()) objs[i].velocity = {vel.data()[2 * i], vel.data()[2 * i + 1]};
          objs[i].stamp_ns = stamp;
        }
        Guard g(v.mutex);
        v.vrs->setMovingObjects(objs);
      }, pb::arg("positions"), pb::arg("velocities") = pb::none(), pb::arg("stamp_ns") = 0,
           "Tracked people (map frame, (K, 2)) the obstacle memory keeps out.")
      .def("update", [](PyVrs& v, int64_t stamp, const pb::handle& pose) {
        const Pose p = toPose(pose, "map_T_base");
        pb::gil_scoped_release nogil;
        Guard g(v.mutex);
        return v.vrs->update(stamp, p);
      }, pb::arg("stamp_ns"), pb::arg("map_T_base"), "The VRS now: a VirtualScan.")
      .def_property_readonly("memory_points", [](PyVrs& v) {
        Guard g(v.mutex);
        const auto pts = v.vrs->memory().points();
        pb::array_t<float> a({static_cast<pb::ssize_t>(pts.size()), pb::ssize_t{2}});
        for (size_t i = 0; i < pts.size(); ++i) a.mutable_at(i, 0) = pts[i].x(), a.mutable_at(i, 1) = pts[i].y();
        return a;
      }, "(K, 2) float32 obstacle memory cells (map frame)")
      .def_property_readonly("counters", [](PyVrs& v) {
        Guard g(v.mutex);
        const VrsCounters& c = v.vrs->counters();
        pb::dict d;
        d["frames"] = c.frames, d["frames_rejected"] = c.frames_rejected, d["updates"] = c.updates;
        d["memory_inserted"] = c.memory_inserted, d["memory_far"] = c.memory_far, d["memory_behind"] = c.memory_behind;
        d["memory_moving"] = c.memory_moving;
        return d;
      });
}

}  // namespace polyloc::py
