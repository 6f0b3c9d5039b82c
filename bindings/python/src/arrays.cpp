// numpy input checks and pose conversions shared by every binding file.
#include "common.hpp"

#include <filesystem>
#include <sstream>

namespace polyloc::py {

void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw pb::error_already_set();
}

void requireExists(const std::string& path, const char* what) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) raise(PyExc_FileNotFoundError, std::string(what) + ": no such file: '" + path + "'");
}

namespace arrays_impl {  // named, not anonymous: the module is compiled in batches (unity build)

std::string shapeText(const pb::array& a) {
  std::ostringstream s;
  s << '(';
  for (pb::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

std::string wanted(const std::vector<pb::ssize_t>& shape) {
  const char* names[] = {"N", "M", "K", "L"};
  std::ostringstream s;
  s << '(';
  for (size_t i = 0; i < shape.size(); ++i) {
    s << (i ? ", " : "");
    if (shape[i] < 0) s << names[std::min<size_t>(i, 3)];
    else s << shape[i];
  }
  s << (shape.size() == 1 ? ",)" : ")");
  return s.str();
}

template <class T>
pb::array_t<T, pb::array::c_style | pb::array::forcecast> checked(const pb::handle& obj, const char* name,
                                                                   const std::vector<pb::ssize_t>& shape,
                                                                   const char* dtype) {
  if (obj.is_none()) raise(PyExc_TypeError, std::string(name) + ": expected an array, got None");
  pb::array raw = pb::array::ensure(obj);
  if (!raw) {
    PyErr_Clear();
    raise(PyExc_TypeError, std::string(name) + ": expected an array of numbers");
  }
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    raise(PyExc_TypeError, std::string(name) + ": expected a numeric array (" + dtype + "), got dtype " +
                               std::string(pb::str(raw.dtype())));
  bool ok = raw.ndim() == static_cast<pb::ssize_t>(shape.size());
  for (size_t i = 0; ok && i < shape.size(); ++i) ok = shape[i] < 0 || raw.shape(i) == shape[i];
  if (!ok)
    raise(PyExc_ValueError, std::string(name) + ": expected shape " + wanted(shape) + ", got " + shapeText(raw));
  auto a = pb::array_t<T, pb::array::c_style | pb::array::forcecast>::ensure(raw);
  if (!a) throw pb::error_already_set();
  return a;
}

}  // namespace arrays_impl

F32Array floatArray(const pb::handle& obj, const char* name, std::vector<pb::ssize_t> shape) {
  using namespace arrays_impl;
  return checked<float>(obj, name, shape, "float32");
}
F64Array doubleArray(const pb::handle& obj, const char* name, std::vector<pb::ssize_t> shape) {
  using namespace arrays_impl;
  return checked<double>(obj, name, shape, "float64");
}
U8Array byteArray(const pb::handle& obj, const char* name, std::vector<pb::ssize_t> shape) {
  using namespace arrays_impl;
  return checked<uint8_t>(obj, name, shape, "uint8");
}

F32Array rangesArray(const pb::handle& obj, const char* name, size_t size) {
  using namespace arrays_impl;
  F32Array a = floatArray(obj, name, {-1});
  if (static_cast<size_t>(a.size()) != size)
    raise(PyExc_ValueError, std::string(name) + ": expected " + std::to_string(size) + " ranges (one per beam), got " +
                                std::to_string(a.size()));
  return a;
}

Pose toPose(const pb::handle& obj, const char* name) {
  using namespace arrays_impl;
  if (pb::isinstance<Pose>(obj)) return obj.cast<Pose>();
  if (obj.is_none()) raise(PyExc_TypeError, std::string(name) + ": expected a Pose, got None");
  pb::array raw = pb::array::ensure(obj);
  if (raw && raw.ndim() == 2) {
    const F64Array m = doubleArray(raw, name, {4, 4});
    return Pose::fromMatrix(Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m.data()));
  }
  if (raw && raw.ndim() == 1) {
    const F64Array v = doubleArray(raw, name, {6});
    const double* p = v.data();
    return Pose::fromXYZRPY(p[0], p[1], p[2], p[3], p[4], p[5]);
  }
  PyErr_Clear();
  raise(PyExc_TypeError, std::string(name) + ": expected a Pose, a (4, 4) matrix or (x, y, z, roll, pitch, yaw)");
}

std::vector<Pose> toPoses(const pb::handle& obj, const char* name) {
  using namespace arrays_impl;
  std::vector<Pose> out;
  if (pb::isinstance<Pose>(obj)) return {obj.cast<Pose>()};
  if (pb::isinstance<pb::array>(obj)) {
    pb::array raw = pb::reinterpret_borrow<pb::array>(obj);
    if (raw.ndim() <= 2) return {toPose(obj, name)};
    const F64Array m = doubleArray(raw, name, {-1, 4, 4});
    for (pb::ssize_t i = 0; i < m.shape(0); ++i)
      out.push_back(Pose::fromMatrix(Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m.data() + 16 * i)));
    return out;
  }
  if (!pb::isinstance<pb::sequence>(obj) || pb::isinstance<pb::str>(obj))
    raise(PyExc_TypeError, std::string(name) + ": expected a sequence of poses or a (P, 4, 4) array");
  for (const pb::handle item : obj) out.push_back(toPose(item, name));
  return out;
}

pb::array_t<double> matrixArray(const Eigen::Matrix<double, 6, 6>& m) {
  using namespace arrays_impl;
  pb::array_t<double> a({6, 6});
  Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(a.mutable_data()) = m;
  return a;
}

Eigen::Matrix<double, 6, 6> toCovariance(const pb::handle& obj, const char* name) {
  using namespace arrays_impl;
  const F64Array c = doubleArray(obj, name, {6, 6});
  return Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(c.data());
}

}  // namespace polyloc::py
