#include <polyloc/mcl/odometry_noise.hpp>
#include <polyloc/mcl/pose_covariance.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace polyloc {
namespace {

// Planar pose error (x, y, yaw) of p moved by d, from an error of p (map frame) to the error of
// the result (map frame): the lever arm of a heading error.
Eigen::Matrix3d composeJacobian(const Pose& p, const Pose& d) {
  const double c = std::cos(p.yaw()), s = std::sin(p.yaw());
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J(0, 2) = -(d.x() * s + d.y() * c);
  J(1, 2) = d.x() * c - d.y() * s;
  return J;
}

}  // namespace

Eigen::Matrix3d motionCovariance(const Pose& delta, const MotionNoise& n) {
  const double dx = delta.x(), dy = delta.y(), dyaw = delta.yaw();
  const double t = std::hypot(dx, dy);
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  if (n.omni) {
    const double st = n.alpha3 * t + n.alpha4 * std::abs(dyaw), sr = n.alpha1 * std::abs(dyaw) + n.alpha2 * t;
    S.diagonal() << st * st, st * st, sr * sr;
    return S;
  }
  // As sampleMotion: rotate-translate-rotate, a backward step folded into a forward one.
  double rot1 = t < 1e-6 ? 0.0 : std::atan2(dy, dx);
  double sign = 1.0;
  if (std::abs(rot1) > M_PI / 2) rot1 = wrapAngle(rot1 + M_PI), sign = -1.0;
  const double rot2 = angleDiff(dyaw, rot1);
  const double s1 = n.alpha1 * std::abs(rot1) + n.alpha2 * t, s2 = n.alpha1 * std::abs(rot2) + n.alpha2 * t;
  const double st = n.alpha3 * t + n.alpha4 * (std::abs(rot1) + std::abs(rot2));
  Eigen::Matrix3d J;  // d(x, y, yaw) / d(rot1, trans, rot2)
  J << -sign * t * std::sin(rot1), sign * std::cos(rot1), 0,  //
      sign * t * std::cos(rot1), sign * std::sin(rot1), 0,    //
      1, 0, 1;
  const Eigen::Vector3d var(s1 * s1, st * st, s2 * s2);
  return J * var.asDiagonal() * J.transpose();
}

Eigen::Matrix3d propagateCovariance(const Eigen::Matrix3d& cov, const Pose& pose, const Pose& delta,
                                    const MotionNoise& noise) {
  const Pose p = pose.planarProjection(), d = delta.planarProjection();
  const Eigen::Matrix3d J = composeJacobian(p, d);
  const double c = std::cos(p.yaw()), s = std::sin(p.yaw());
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // the start frame into the map frame
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return J * cov * J.transpose() + R * motionCovariance(d, noise) * R.transpose();
}

bool OdometryNoise::addPair(const Pose& prev, const Eigen::Matrix<double, 6, 6>& prev_cov, const Pose& now,
                            const Eigen::Matrix<double, 6, 6>& now_cov, const Pose& odom_delta, const MotionNoise& base) {
  const Pose delta = odom_delta.planarProjection();
  if (std::hypot(delta.x(), delta.y()) < config_.min_step && std::abs(delta.yaw()) < config_.min_turn) return false;
  if (!prev_cov.allFinite() || !now_cov.allFinite()) return false;
  const Pose predicted = prev.planarProjection() * delta;
  const Pose e = predicted.inverse() * now.planarProjection();
  const Eigen::Vector3d err(e.x(), e.y(), e.yaw());
  // Everything in the predicted pose's frame: the motion model's noise already is; the previous
  // estimate's error moves with the step (lever arm), both rotate into that frame.
  const double c = std::cos(predicted.yaw()), s = std::sin(predicted.yaw());
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() << c, s, -s, c;
  const Eigen::Matrix3d Jp = composeJacobian(prev.planarProjection(), delta);
  const Eigen::Matrix3d S = motionCovariance(delta, scaled(base)) +
                            R * (Jp * planarCovariance(prev_cov) * Jp.transpose() + planarCovariance(now_cov)) * R.transpose() +
                            Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal().toDenseMatrix();
  const Eigen::Matrix2d Sxy = S.topLeftCorner<2, 2>();
  const Eigen::LDLT<Eigen::Matrix2d> ldlt(Sxy);
  if (ldlt.info() != Eigen::Success || !(S(2, 2) > 0)) return false;
  last_nis_xy_ = err.head<2>().dot(ldlt.solve(err.head<2>()));
  last_nis_yaw_ = err[2] * err[2] / S(2, 2);
  // Log-ratio smoothing of the variance scale: NIS / dof is the ratio of the actual to the
  // assumed variance; its log is clamped so that a slip (or a refinement in a wrong place) moves
  // the scale by a bounded factor.
  const auto follow = [&](double& scale, double ratio) {
    const double lr = std::clamp(std::log(std::max(ratio, 1e-9)), -config_.max_log_ratio, config_.max_log_ratio);
    const double var = scale * scale * std::exp(config_.gain * lr);
    scale = std::clamp(std::sqrt(var), config_.min_scale, config_.max_scale);
  };
  follow(trans_, last_nis_xy_ / 2);
  follow(rot_, last_nis_yaw_);
  ++pairs_;
  return true;
}

MotionNoise OdometryNoise::scaled(const MotionNoise& base) const {
  MotionNoise n = base;
  n.alpha3 *= trans_, n.alpha4 *= trans_;
  n.alpha1 *= rot_, n.alpha2 *= rot_;
  return n;
}

}  // namespace polyloc
