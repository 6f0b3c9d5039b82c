// Pose (SE(3), double) and the angle helpers.
#include "common.hpp"

#include <pybind11/operators.h>

#include <fmt/core.h>

namespace polyloc::py {

namespace geometry_impl {  // named, not anonymous: the module is compiled in batches (unity build)

pb::array_t<double> vec(const Eigen::Vector3d& v) {
  pb::array_t<double> a(3);
  std::copy(v.data(), v.data() + 3, a.mutable_data());
  return a;
}

// Points (3,) or (N, 3) through a pose.
pb::array_t<double> transformPoints(const Pose& p, const pb::handle& points) {
  const bool single = pb::array::ensure(points) && pb::array::ensure(points).ndim() == 1;
  const F64Array in = single ? doubleArray(points, "points", {3}) : doubleArray(points, "points", {-1, 3});
  const pb::ssize_t n = single ? 1 : in.shape(0);
  pb::array_t<double> out = single ? pb::array_t<double>(3) : pb::array_t<double>({n, pb::ssize_t{3}});
  const double* s = in.data();
  double* d = out.mutable_data();
  for (pb::ssize_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = p * Eigen::Vector3d(s[3 * i], s[3 * i + 1], s[3 * i + 2]);
    d[3 * i] = q.x(), d[3 * i + 1] = q.y(), d[3 * i + 2] = q.z();
  }
  return out;
}

}  // namespace geometry_impl

void bindGeometry(pb::module_& m) {
  using namespace geometry_impl;
  pb::class_<Pose>(m, "Pose", R"(A rigid transform in 3D (SE(3)): rotation as a unit quaternion, translation in metres.

A Pose maps points of its child frame into its parent frame: ``p_parent = pose * p_child``;
``map_T_base * base_T_sensor`` is ``map_T_sensor``. Angles are radians; roll about x, then pitch
about y, then yaw about z (R = Rz(yaw) Ry(pitch) Rx(roll)), as in ROS.

Wherever polyloc takes a pose it also takes a (4, 4) matrix or a sequence
(x, y, z, roll, pitch, yaw).)")
      .def(pb::init([](double x, double y, double z, double roll, double pitch, double yaw) {
  using namespace geometry_impl;
             return Pose::fromXYZRPY(x, y, z, roll, pitch, yaw);
           }),
           pb::arg("x") = 0.0, pb::arg("y") = 0.0, pb::arg("z") = 0.0, pb::arg("roll") = 0.0, pb::arg("pitch") = 0.0,
           pb::arg("yaw") = 0.0, "Pose from position (m) and roll, pitch, yaw (rad).")
      .def_static("from_xyzrpy", &Pose::fromXYZRPY, pb::arg("x"), pb::arg("y"), pb::arg("z"), pb::arg("roll"),
                  pb::arg("pitch"), pb::arg("yaw"))
      .def_static("planar", &Pose::planar, pb::arg("x"), pb::arg("y"), pb::arg("yaw"), "x, y on the floor, turned by yaw.")
      .def_static("from_matrix", [](const pb::handle& m) {
                    const F64Array a = doubleArray(m, "matrix", {4, 4});
                    return Pose::fromMatrix(Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(a.data()));
                  },
                  pb::arg("matrix"), "From a homogeneous (4, 4) matrix; its rotation part is orthonormalised.")
      .def_static("from_quaternion",
                  [](const pb::handle& wxyz, const pb::handle& t) {
                    const F64Array q = doubleArray(wxyz, "wxyz", {4});
                    const F64Array v = doubleArray(t, "translation", {3});
                    return Pose(Eigen::Quaterniond(q.data()[0], q.data()[1], q.data()[2], q.data()[3]),
                                Eigen::Vector3d(v.data()[0], v.data()[1], v.data()[2]));
                  },
                  pb::arg("wxyz"), pb::arg("translation"), "From a quaternion (w, x, y, z) and a translation (normalised).")
      .def_static("interpolate", &Pose::interpolate, pb::arg("a"), pb::arg("b"), pb::arg("s"),
                  "Geodesic interpolation: s = 0 gives a, s = 1 gives b.")
      .def_property_readonly("x", &Pose::x)
      .def_property_readonly("y", &Pose::y)
      .def_property_readonly("z", &Pose::z)
      .def_property_readonly("roll", &Pose::roll)
      .def_property_readonly("pitch", &Pose::pitch)
      .def_property_readonly("yaw", &Pose::yaw)
      .def_property_readonly("translation", [](const Pose& p) { return vec(p.translation()); }, "(3,) float64, metres")
      .def_property_readonly("quaternion",
                             [](const Pose& p) {
                               const auto& q = p.rotation();
                               pb::array_t<double> a(4);
                               double* d = a.mutable_data();
                               d[0] = q.w(), d[1] = q.x(), d[2] = q.y(), d[3] = q.z();
                               return a;
                             },
                             "(4,) float64: w, x, y, z")
      .def("matrix",
           [](const Pose& p) {
             pb::array_t<double> a({4, 4});
             Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(a.mutable_data()) = p.matrix();
             return a;
           },
           "Homogeneous (4, 4) float64 matrix.")
      .def("to_xyzrpy",
           [](const Pose& p) {
             pb::array_t<double> a(6);
             double* d = a.mutable_data();
             d[0] = p.x(), d[1] = p.y(), d[2] = p.z(), d[3] = p.roll(), d[4] = p.pitch(), d[5] = p.yaw();
             return a;
           },
           "(6,) float64: x, y, z, roll, pitch, yaw.")
      .def("inverse", &Pose::inverse)
      .def("planar_projection", &Pose::planarProjection, "Keep x, y, yaw; z = roll = pitch = 0.")
      .def("is_approx", &Pose::isApprox, pb::arg("other"), pb::arg("eps") = 1e-9)
      .def(pb::self * pb::self)
      .def("__mul__", &transformPoints, pb::arg("points"), "Points (3,) or (N, 3) mapped into the parent frame.")
      .def("transform", &transformPoints, pb::arg("points"), "Points (3,) or (N, 3) mapped into the parent frame.")
      .def("__repr__",
           [](const Pose& p) {
             return fmt::format("Pose(x={:.4f}, y={:.4f}, z={:.4f}, roll={:.4f}, pitch={:.4f}, yaw={:.4f})", p.x(), p.y(),
                                p.z(), p.roll(), p.pitch(), p.yaw());
           })
      .def(pb::pickle([](const Pose& p) { return pb::make_tuple(p.x(), p.y(), p.z(), p.rotation().w(), p.rotation().x(),
                                                                 p.rotation().y(), p.rotation().z()); },
                      [](const pb::tuple& t) {
                        return Pose(Eigen::Quaterniond(t[3].cast<double>(), t[4].cast<double>(), t[5].cast<double>(),
                                                       t[6].cast<double>()),
                                    Eigen::Vector3d(t[0].cast<double>(), t[1].cast<double>(), t[2].cast<double>()));
                      }));

  m.def("wrap_angle", &wrapAngle, pb::arg("angle"), "Angle wrapped to (-pi, pi].");
  m.def("angle_diff", &angleDiff, pb::arg("a"), pb::arg("b"), "Shortest signed difference a - b (rad).");
}

}  // namespace polyloc::py
