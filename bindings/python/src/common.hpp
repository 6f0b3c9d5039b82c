// Shared by the binding files: numpy checks and conversions, errors with Python's types, and the
// bind* functions module.cpp calls (one per concept, each in its own file).
#pragma once

#include <polyloc/geometry/pose.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace polyloc::py {

namespace pb = pybind11;

// C-contiguous arrays; forcecast turns float64 (or int) input into the dtype, copying only then.
using F32Array = pb::array_t<float, pb::array::c_style | pb::array::forcecast>;
using F64Array = pb::array_t<double, pb::array::c_style | pb::array::forcecast>;
using U8Array = pb::array_t<uint8_t, pb::array::c_style | pb::array::forcecast>;

// Raise a Python exception of the given type with a message (e.g. PyExc_ValueError).
[[noreturn]] void raise(PyObject* type, const std::string& message);
// FileNotFoundError naming the call and the path, unless the path exists.
void requireExists(const std::string& path, const char* what);

// `obj` as a C-contiguous array of `T` with the given shape; -1 is any size. Raises TypeError for
// a dtype that is not numeric (strings, objects) and ValueError for a wrong shape, naming `name`.
F32Array floatArray(const pb::handle& obj, const char* name, std::vector<pb::ssize_t> shape);
F64Array doubleArray(const pb::handle& obj, const char* name, std::vector<pb::ssize_t> shape);
U8Array byteArray(const pb::handle& obj, const char* name, std::vector<pb::ssize_t> shape);

// Copies of plain vectors as 1-D arrays.
template <class T>
pb::array_t<T> toArray(const std::vector<T>& v) {
  pb::array_t<T> a(static_cast<pb::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}
// A read-only view of memory owned by `owner` (kept alive by the array).
template <class T>
pb::array_t<T> view(const T* data, std::vector<pb::ssize_t> shape, const pb::handle& owner) {
  pb::array_t<T> a(shape, data, owner);
  pb::detail::array_proxy(a.ptr())->flags &= ~pb::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// Poses from Python: a Pose, a (4, 4) matrix, or (x, y, z, roll, pitch, yaw); lists of them or a
// (P, 4, 4) array for batches.
Pose toPose(const pb::handle& obj, const char* name);
std::vector<Pose> toPoses(const pb::handle& obj, const char* name);
pb::array_t<double> matrixArray(const Eigen::Matrix<double, 6, 6>& m);
Eigen::Matrix<double, 6, 6> toCovariance(const pb::handle& obj, const char* name);

// A 1-D float32 range array of `size` entries (ranges of a frame in beam order).
F32Array rangesArray(const pb::handle& obj, const char* name, size_t size);

// Serialises calls into one object whose methods drop the GIL (two Python threads would
// otherwise run its C++ state at the same time). Lock after releasing the GIL.
using Guard = std::lock_guard<std::mutex>;

void bindGeometry(pb::module_& m);
void bindMap(pb::module_& m);
void bindSensors(pb::module_& m);
void bindConfig(pb::module_& m);
void bindMclConfig(pb::module_& m);
void bindRaycast(pb::module_& m);
void bindLocalizer(pb::module_& m);
void bindSimulator(pb::module_& m);
void bindDepth(pb::module_& m);
void bindVrs(pb::module_& m);
void bindTracking(pb::module_& m);
void bindRecording(pb::module_& m);
void bindShm(pb::module_& m);  // polyloc.shm: the shared-memory client (service/shm)
void bindShmDaemon(pb::module_& m);  // polyloc.shm.daemon_channels: polylocd's channel table (after bindShm)

}  // namespace polyloc::py
