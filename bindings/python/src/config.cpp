// The polyloc configuration file (maps/config/*.yaml): map, robot, rig and the sections of the
// kernels, each a bound settings struct (mcl_config.cpp, depth.cpp, vrs.cpp, tracking.cpp).
#include "common.hpp"

#include <polyloc/configfile/polyloc_config.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

namespace polyloc::py {

namespace config_impl {  // named, not anonymous: the module is compiled in batches (unity build)

const char* upAxisName(UpAxis a) {
  switch (a) {
    case UpAxis::Z: return "z";
    case UpAxis::Y: return "y";
    case UpAxis::X: return "x";
    case UpAxis::Auto: break;
  }
  return "auto";
}

}  // namespace config_impl

void bindConfig(pb::module_& m) {
  using namespace config_impl;
  pb::class_<RobotSpec>(m, "RobotSpec", "The robot's body: footprint (or radius), height, kinematics.")
      .def(pb::init<>())
      .def_property_readonly("footprint", [](const RobotSpec& r) {
        pb::array_t<double> a({static_cast<pb::ssize_t>(r.footprint.size()), pb::ssize_t{2}});
        for (size_t i = 0; i < r.footprint.size(); ++i) a.mutable_at(i, 0) = r.footprint[i].x(), a.mutable_at(i, 1) = r.footprint[i].y();
        return a;
      }, "(K, 2) float64 polygon in base_link; empty for a round robot")
      .def_readwrite("radius", &RobotSpec::radius, "m, for a round robot")
      .def_readwrite("height", &RobotSpec::height, "m")
      .def_property_readonly("kinematics", [](const RobotSpec& r) { return std::string(kinematicsName(r.kinematics)); })
      .def_property_readonly("bounding_radius", &RobotSpec::boundingRadius);

  pb::class_<PolylocConfig>(m, "Config", R"(A polyloc configuration file: map, robot, rig, mcl, vrs, tracking, depth_filter.

Sections are the settings structs the kernels take; they can be changed before they are passed on
(``cfg.mcl.particles = 500``).)")
      .def_readonly("file", &PolylocConfig::file)
      .def_property_readonly("map_file", [](const PolylocConfig& c) { return c.map.file; }, "resolved path of the map")
      .def_property_readonly("map_scale", [](const PolylocConfig& c) { return c.map.load.scale; })
      .def_property_readonly("map_up_axis", [](const PolylocConfig& c) { return std::string(upAxisName(c.map.load.up_axis)); })
      .def_readwrite("robot", &PolylocConfig::robot)
      .def_readwrite("rig", &PolylocConfig::rig)
      .def_readwrite("mcl", &PolylocConfig::mcl)
      .def_readwrite("vrs", &PolylocConfig::vrs)
      .def_readwrite("tracking", &PolylocConfig::tracking)
      .def_readwrite("depth_filter", &PolylocConfig::depth_filter)
      .def("__repr__", [](const PolylocConfig& c) {
  using namespace config_impl;
        return fmt::format("<polyloc.Config '{}': map '{}', rig '{}' with {} sensors>", c.file, c.map.file, c.rig.name, c.rig.size());
      });

  m.def("load_config", [](const std::string& path) {
    requireExists(path, "load_config");
    return loadConfig(path);
  }, pb::arg("path"), R"(Read a polyloc configuration file (maps/config/lab.yaml, ...).

Raises FileNotFoundError for a missing file and ConfigError (a ValueError) naming file, line and
key for unknown keys, bad values or a map file that does not exist.)");
}

}  // namespace polyloc::py
