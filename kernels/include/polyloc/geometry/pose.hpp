// SE(3) pose on Eigen: rotation as a unit quaternion, translation in metres (double).
// A Pose maps points from its child frame into its parent frame: p_parent = pose * p_child,
// e.g. map_T_base * base_T_sensor = map_T_sensor (REP-103 frames, z up).
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <Eigen/Geometry>

namespace polyloc {

// Yaw (rad) of the unit quaternion (w, x, y, z): the rotation about z of R = Rz Ry Rx, as
// tf2::getYaw. One place for it: Pose::yaw, particle sets, the C client.
inline double yawOfQuaternion(double w, double x, double y, double z) {
  return std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

class Pose {
 public:
  Pose() : q_(Eigen::Quaterniond::Identity()), t_(Eigen::Vector3d::Zero()) {}
  Pose(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) : q_(q.normalized()), t_(t) {}

  // Roll about x, then pitch about y, then yaw about z (R = Rz(yaw) Ry(pitch) Rx(roll)), as ROS.
  static Pose fromXYZRPY(double x, double y, double z, double roll, double pitch, double yaw);
  static Pose planar(double x, double y, double yaw) { return fromXYZRPY(x, y, 0, 0, 0, yaw); }
  static Pose fromMatrix(const Eigen::Matrix4d& m);

  const Eigen::Quaterniond& rotation() const { return q_; }
  const Eigen::Vector3d& translation() const { return t_; }
  double x() const { return t_.x(); }
  double y() const { return t_.y(); }
  double z() const { return t_.z(); }
  double roll() const;
  double pitch() const;
  double yaw() const;
  Eigen::Matrix4d matrix() const;

  Pose operator*(const Pose& o) const { return Pose(q_ * o.q_, t_ + q_ * o.t_); }
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return q_ * p + t_; }
  Eigen::Vector3d rotate(const Eigen::Vector3d& v) const { return q_ * v; }
  Pose inverse() const;

  // Projection onto the floor plane: keep x, y, yaw; z = 0, roll = pitch = 0.
  Pose planarProjection() const { return planar(x(), y(), yaw()); }
  // Geodesic interpolation: s = 0 gives a, s = 1 gives b (slerp + linear translation).
  static Pose interpolate(const Pose& a, const Pose& b, double s);

  bool isApprox(const Pose& o, double eps = 1e-9) const;

 private:
  Eigen::Quaterniond q_;
  Eigen::Vector3d t_;
};

// Angle helpers: wrap to (-pi, pi], shortest signed difference a - b.
double wrapAngle(double a);
double angleDiff(double a, double b);
inline constexpr double deg2rad(double d) { return d * 3.14159265358979323846 / 180.0; }
inline constexpr double rad2deg(double r) { return r * 180.0 / 3.14159265358979323846; }

}  // namespace polyloc
