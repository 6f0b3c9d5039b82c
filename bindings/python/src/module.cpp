// The extension module polyloc._polyloc; the package polyloc (bindings/python/polyloc) re-exports
// it. polyloc's own error types become Python exceptions that derive from the builtin a caller
// would catch: MapError and RecordingError are OSErrors, ConfigError is a ValueError. The rest
// follows pybind11: std::invalid_argument -> ValueError, std::out_of_range -> IndexError, other
// std::exceptions -> RuntimeError, always with the C++ message.
#include "common.hpp"

#include <polyloc/config/yaml.hpp>
#include <polyloc/io/error.hpp>
#include <polyloc/map/load.hpp>

PYBIND11_MODULE(_polyloc, m) {
  namespace py = polyloc::py;
  m.doc() = "polyloc: polygon-map localisation, ray casting, simulation and depth filtering (C++ kernels)";
  pybind11::register_exception<polyloc::MapError>(m, "MapError", PyExc_OSError);
  pybind11::register_exception<polyloc::IoError>(m, "RecordingError", PyExc_OSError);
  pybind11::register_exception<polyloc::ConfigError>(m, "ConfigError", PyExc_ValueError);

  py::bindGeometry(m);
  py::bindMap(m);
  py::bindSensors(m);
  py::bindMclConfig(m);
  py::bindConfig(m);
  py::bindRaycast(m);
  py::bindLocalizer(m);
  py::bindSimulator(m);
  py::bindDepth(m);
  py::bindVrs(m);
  py::bindTracking(m);
  py::bindRecording(m);
  py::bindShm(m);  // the submodule _shm, re-exported by polyloc/shm.py as polyloc.shm
  py::bindShmDaemon(m);
}
