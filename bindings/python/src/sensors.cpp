// Sensor models, their beams, and rigs (sensors with names and mounts).
#include "common.hpp"

#include <polyloc/sensors/rig.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

namespace polyloc::py {

namespace sensors_impl {  // named, not anonymous: the module is compiled in batches (unity build)

pb::array_t<float> directions(const BeamSet& b) {
  const auto n = static_cast<pb::ssize_t>(b.size());
  pb::array_t<float> a({n, pb::ssize_t{3}});
  float* d = a.mutable_data();
  for (pb::ssize_t i = 0; i < n; ++i) d[3 * i] = b.dx[i], d[3 * i + 1] = b.dy[i], d[3 * i + 2] = b.dz[i];
  return a;
}

BeamSet beamsFromArray(const pb::handle& dirs, float range_min, float range_max) {
  const F32Array a = floatArray(dirs, "directions", {-1, 3});
  if (!(range_min >= 0 && range_max > range_min))
    raise(PyExc_ValueError, fmt::format("BeamSet: need 0 <= range_min < range_max, got {} and {}", range_min, range_max));
  BeamSet b;
  b.range_min = range_min, b.range_max = range_max;
  for (pb::ssize_t i = 0; i < a.shape(0); ++i) {
    const Eigen::Vector3f d(a.data()[3 * i], a.data()[3 * i + 1], a.data()[3 * i + 2]);
    const float n = d.norm();
    if (!(n > 0) || !std::isfinite(n)) raise(PyExc_ValueError, fmt::format("directions: row {} is zero or not finite", i));
    b.push(d.x() / n, d.y() / n, d.z() / n);  // the casters need unit directions
  }
  return b;
}

const Sensor& sensorAt(const Rig& rig, const pb::handle& key) {
  if (pb::isinstance<pb::str>(key)) {
    const int i = rig.find(key.cast<std::string>());
    if (i < 0) throw pb::key_error(fmt::format("rig '{}' has no sensor '{}'", rig.name, key.cast<std::string>()));
    return rig.sensors[i];
  }
  auto i = key.cast<int64_t>();
  if (i < 0) i += static_cast<int64_t>(rig.size());
  if (i < 0 || static_cast<size_t>(i) >= rig.size())
    throw pb::index_error(fmt::format("sensor index {} out of range: rig '{}' has {}", key.cast<int64_t>(), rig.name, rig.size()));
  return rig.sensors[i];
}

}  // namespace sensors_impl

void bindSensors(pb::module_& m) {
  using namespace sensors_impl;
  pb::class_<BeamSet>(m, "BeamSet", "Unit beam directions of one sensor in its own frame (x forward, y left, z up) and its range limits.")
      .def(pb::init(&beamsFromArray), pb::arg("directions"), pb::arg("range_min") = 0.f, pb::arg("range_max") = 30.f,
           "From (B, 3) directions (normalised here).")
      .def_property_readonly("directions", &directions, "(B, 3) float32 unit vectors")
      .def_readwrite("range_min", &BeamSet::range_min)
      .def_readwrite("range_max", &BeamSet::range_max)
      .def("__len__", &BeamSet::size)
      .def("__repr__", [](const BeamSet& b) { return fmt::format("<polyloc.BeamSet {} beams, {} .. {} m>", b.size(), b.range_min, b.range_max); });

  pb::class_<PlanarScannerSpec>(m, "PlanarScannerSpec", "2D laser scanner: beams fanned in the x-y plane, counter-clockwise from -fov/2.")
      .def(pb::init<>())
      .def_readwrite("fov", &PlanarScannerSpec::fov_rad, "rad")
      .def_readwrite("resolution", &PlanarScannerSpec::resolution_rad, "rad")
      .def_readwrite("range_min", &PlanarScannerSpec::range_min)
      .def_readwrite("range_max", &PlanarScannerSpec::range_max)
      .def_readwrite("rate_hz", &PlanarScannerSpec::rate_hz)
      .def_property_readonly("num_beams", &PlanarScannerSpec::numBeams)
      .def_property_readonly("angle_min", &PlanarScannerSpec::angleMin)
      .def("beams", &PlanarScannerSpec::beams);
  pb::class_<LidarSpec>(m, "LidarSpec", "Multi-layer spinning lidar; beams layer-major.")
      .def(pb::init<>())
      .def_readwrite("elevations", &LidarSpec::elevations_rad, "rad, one per layer")
      .def_readwrite("azimuth_resolution", &LidarSpec::azimuth_resolution_rad, "rad")
      .def_readwrite("range_min", &LidarSpec::range_min)
      .def_readwrite("range_max", &LidarSpec::range_max)
      .def_readwrite("rate_hz", &LidarSpec::rate_hz)
      .def_property_readonly("num_beams", &LidarSpec::numBeams)
      .def("beams", &LidarSpec::beams);
  pb::class_<DepthCameraSpec>(m, "DepthCameraSpec", "Pinhole depth / ToF camera; beams are pixel rays, row-major from the top left.")
      .def(pb::init<>())
      .def_readwrite("width", &DepthCameraSpec::width)
      .def_readwrite("height", &DepthCameraSpec::height)
      .def_readwrite("hfov", &DepthCameraSpec::hfov_rad, "rad")
      .def_readwrite("vfov", &DepthCameraSpec::vfov_rad, "rad")
      .def_readwrite("range_min", &DepthCameraSpec::range_min)
      .def_readwrite("range_max", &DepthCameraSpec::range_max)
      .def_readwrite("rate_hz", &DepthCameraSpec::rate_hz)
      .def_property_readonly("fx", &DepthCameraSpec::fx)
      .def_property_readonly("fy", &DepthCameraSpec::fy)
      .def_property_readonly("cx", &DepthCameraSpec::cx)
      .def_property_readonly("cy", &DepthCameraSpec::cy)
      .def_property_readonly("num_beams", &DepthCameraSpec::numBeams)
      .def("beams", &DepthCameraSpec::beams)
      .def("depth_factors", [](const DepthCameraSpec& c) {
        pb::array_t<float> a = toArray(c.depthFactors());
        return a.reshape({c.height, c.width});
      }, "(H, W) float32: depth = range * factor");

  m.def("depth_camera_from_intrinsics", &depthCameraFromIntrinsics, pb::arg("width"), pb::arg("height"), pb::arg("fx"),
        pb::arg("fy"), pb::arg("cx"), pb::arg("cy"), pb::arg("range_min") = 0.1, pb::arg("range_max") = 10.0,
        pb::arg("rate_hz") = 30.0,
        "A calibrated depth camera from CameraInfo's K (pixels; the first pixel's centre is 0). ValueError names a bad value.");
  m.def("sensor_preset", &sensorPreset, pb::arg("name"), "Spec of a preset: sick_s300, hokuyo_urg04lx, sick_lms200, vlp16, pmd_o3d100.");
  m.def("sensor_preset_names", &sensorPresetNames);

  pb::class_<Sensor>(m, "Sensor", "A mounted sensor: a name, a spec and its mount (base_link -> sensor).")
      .def(pb::init([](std::string name, SensorSpec spec, const pb::handle& mount) {
             return Sensor{std::move(name), std::move(spec), mount.is_none() ? Pose() : toPose(mount, "mount")};
           }),
           pb::arg("name"), pb::arg("spec"), pb::arg("mount") = pb::none())
      .def_readonly("name", &Sensor::name)
      .def_readonly("spec", &Sensor::spec)
      .def_readonly("mount", &Sensor::mount, "base_T_sensor")
      .def_property_readonly("kind", &Sensor::typeName, "'planar_scanner', 'lidar' or 'depth_camera'")
      .def_property_readonly("rate_hz", &Sensor::rateHz)
      .def_property_readonly("num_beams", [](const Sensor& s) { return s.beams().size(); })
      .def("beams", &Sensor::beams)
      .def("world_pose", [](const Sensor& s, const pb::handle& p) { return s.worldPose(toPose(p, "map_T_base")); },
           pb::arg("map_T_base"), "map_T_sensor for a robot at map_T_base")
      .def("__repr__", [](const Sensor& s) {
        return fmt::format("<polyloc.Sensor '{}' {} with {} beams>", s.name, s.typeName(), s.beams().size());
      });

  pb::class_<Rig>(m, "Rig", "The sensors mounted on one robot; index by position or name.")
      .def(pb::init<>())
      .def_readwrite("name", &Rig::name)
      .def_readonly("sensors", &Rig::sensors)
      .def_readonly("presets", &Rig::presets)
      .def("add", [](Rig& r, const Sensor& s, std::string preset) { r.add(s, std::move(preset)); }, pb::arg("sensor"),
           pb::arg("preset") = "")
      .def("find", &Rig::find, pb::arg("name"), "index of a sensor, or -1")
      .def_property_readonly("names", [](const Rig& r) {
        std::vector<std::string> n;
        for (const auto& s : r.sensors) n.push_back(s.name);
        return n;
      })
      .def("__len__", &Rig::size)
      .def("__getitem__", &sensorAt, pb::return_value_policy::reference_internal)
      .def("__iter__", [](const Rig& r) { return pb::make_iterator(r.sensors.begin(), r.sensors.end()); }, pb::keep_alive<0, 1>())
      .def("__repr__", [](const Rig& r) { return fmt::format("<polyloc.Rig '{}' with {} sensors>", r.name, r.size()); });
  m.def("rig_preset", &rigPreset, pb::arg("name"), "A built-in rig: 'lisa' or 'taser'.");
  m.def("rig_preset_names", &rigPresetNames);
  m.def("load_rig", [](const std::string& path) {
    requireExists(path, "load_rig");
    return loadRig(path);
  }, pb::arg("path"), "A rig YAML file (maps/rigs/*.yaml). Raises ConfigError naming file, line and key.");
}

}  // namespace polyloc::py
