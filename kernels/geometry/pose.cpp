#include <polyloc/geometry/pose.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc {

Pose Pose::fromXYZRPY(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  return Pose(q, Eigen::Vector3d(x, y, z));
}

Pose Pose::fromMatrix(const Eigen::Matrix4d& m) {
  return Pose(Eigen::Quaterniond(Eigen::Matrix3d(m.topLeftCorner<3, 3>())), m.topRightCorner<3, 1>());
}

// ZYX Euler angles read from the rotation matrix; pitch is clamped at the gimbal-lock poles.
double Pose::roll() const {
  const Eigen::Matrix3d r = q_.toRotationMatrix();
  return std::atan2(r(2, 1), r(2, 2));
}
double Pose::pitch() const {
  const Eigen::Matrix3d r = q_.toRotationMatrix();
  return std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
}
double Pose::yaw() const {
  return yawOfQuaternion(q_.w(), q_.x(), q_.y(), q_.z());  // bit for bit what the rotation matrix gives
}

Eigen::Matrix4d Pose::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = q_.toRotationMatrix();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

Pose Pose::inverse() const {
  const Eigen::Quaterniond qi = q_.conjugate();
  return Pose(qi, -(qi * t_));
}

Pose Pose::interpolate(const Pose& a, const Pose& b, double s) {
  return Pose(a.q_.slerp(s, b.q_), (1.0 - s) * a.t_ + s * b.t_);
}

bool Pose::isApprox(const Pose& o, double eps) const {
  // q and -q are the same rotation.
  return (t_ - o.t_).norm() <= eps && std::abs(std::abs(q_.dot(o.q_)) - 1.0) <= eps;
}

double wrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);  // [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

double angleDiff(double a, double b) { return wrapAngle(a - b); }

}  // namespace polyloc
