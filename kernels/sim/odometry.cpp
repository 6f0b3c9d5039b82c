#include <polyloc/sim/odometry.hpp>

#include <cmath>

namespace polyloc {

namespace {
constexpr uint64_t kOdometryStream = 0x4F444F4DULL;  // "ODOM"
}

OdometrySimulator::OdometrySimulator(const OdometryNoise& noise, bool enabled, uint64_t seed)
    : noise_(noise), enabled_(enabled), rng_(seed) {}

void OdometrySimulator::reset(const Pose& map_T_base) {
  prev_ = map_T_base;
  x_ = y_ = yaw_ = 0;
  odom_T_base_ = Pose();
  twist_.setZero();
  var_.setZero();
  tick_ = 0;
}

// The textbook decomposition (rotate rot1, translate trans, rotate rot2) in the previous base
// frame, with variances linear in the motion; rotation noise is split evenly over rot1 and rot2.
void OdometrySimulator::step(const Pose& map_T_base, double dt) {
  ++tick_;
  const Eigen::Vector3d d3 = map_T_base.translation() - prev_.translation();
  const double yaw0 = prev_.yaw(), yaw1 = map_T_base.yaw();
  const double c = std::cos(yaw0), s = std::sin(yaw0);
  const double fx = c * d3.x() + s * d3.y(), fy = -s * d3.x() + c * d3.y();  // previous base frame
  const double planar = std::hypot(fx, fy);
  const double dyaw = angleDiff(yaw1, yaw0);
  // Wheels roll along the surface: they measure the 3D distance, odometry counts it as planar.
  const double trans = d3.norm();
  const double rot1 = planar > 1e-9 ? std::atan2(fy, fx) : 0.0;
  const double rot2 = angleDiff(dyaw, rot1);
  const double tilt = std::abs(angleDiff(map_T_base.roll(), prev_.roll())) +
                      std::abs(angleDiff(map_T_base.pitch(), prev_.pitch()));
  double n_rot1 = 0, n_rot2 = 0, n_trans = 0;
  double var_rot = 0, var_trans = 0;
  if (enabled_) {
    const double arot = std::abs(dyaw);
    var_rot = noise_.alpha1 * arot + noise_.alpha2 * trans + noise_.slip_rotation * tilt;
    var_trans = noise_.alpha3 * trans + noise_.alpha4 * arot + noise_.slip_translation * tilt;
    n_rot1 = std::sqrt(0.5 * var_rot) * rng_.normal(kOdometryStream, tick_, 0);
    n_rot2 = std::sqrt(0.5 * var_rot) * rng_.normal(kOdometryStream, tick_, 1);
    n_trans = std::sqrt(var_trans) * rng_.normal(kOdometryStream, tick_, 2);
  }
  const double mt = (enabled_ ? trans : planar) + n_trans;
  const double mr1 = rot1 + n_rot1, mr2 = rot2 + n_rot2;
  const double heading = yaw_ + mr1;
  x_ += mt * std::cos(heading);
  y_ += mt * std::sin(heading);
  yaw_ = wrapAngle(yaw_ + mr1 + mr2);
  odom_T_base_ = Pose::planar(x_, y_, yaw_);
  if (dt > 0) twist_ = Eigen::Vector3d(mt * std::cos(mr1) / dt, mt * std::sin(mr1) / dt, (mr1 + mr2) / dt);
  // Drift grows as a random walk: along the heading by var_trans, sideways by trans^2 var_rot/2.
  const double ch = std::cos(heading), sh = std::sin(heading);
  const double lateral = mt * mt * 0.5 * var_rot;
  var_.x() += var_trans * ch * ch + lateral * sh * sh;
  var_.y() += var_trans * sh * sh + lateral * ch * ch;
  var_.z() += var_rot;
  prev_ = map_T_base;
}

}  // namespace polyloc
