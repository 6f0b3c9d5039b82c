// Constant-velocity Kalman filter in the plane: state (x, y, vx, vy), position measurements.
// The motion model is white-noise acceleration (discretised, Bar-Shalom's "DWNA"): people walk
// at a roughly steady pace and turn or stop now and then.
#pragma once

#include <Eigen/Core>

namespace polyloc {

// Semi-axes (m) and the angle of the major axis from the x axis (rad, (-pi/2, pi/2]) of a
// covariance's ellipse at `sigmas` standard deviations.
struct Ellipse {
  double major = 0, minor = 0, angle = 0;
};
Ellipse covarianceEllipse(const Eigen::Matrix2d& cov, double sigmas = 1.0);

class ConstantVelocityKalman {
 public:
  using Vector4 = Eigen::Vector4d;
  using Matrix4 = Eigen::Matrix4d;

  ConstantVelocityKalman() = default;
  ConstantVelocityKalman(const Vector4& x, const Matrix4& P) : x_(x), P_(P) {}
  // At rest at `position` with its covariance; velocity 0 with std `speed_sigma` per axis.
  static ConstantVelocityKalman start(const Eigen::Vector2d& position, const Eigen::Matrix2d& cov,
                                      double speed_sigma);

  // x <- F x, P <- F P F' + Q(dt); dt <= 0 changes nothing.
  void predict(double dt, double acceleration_sigma);
  // Innovation covariance H P H' + R of a position measurement with covariance R.
  Eigen::Matrix2d innovation(const Eigen::Matrix2d& R) const;
  // Squared Mahalanobis distance of measurement z (covariance R) from the predicted position.
  double mahalanobis2(const Eigen::Vector2d& z, const Eigen::Matrix2d& R) const;
  // Standard update, covariance in Joseph form (stays symmetric positive definite).
  void update(const Eigen::Vector2d& z, const Eigen::Matrix2d& R);
  // Scales the velocity down to `max_speed` when it is faster (covariance kept).
  void clampSpeed(double max_speed);

  const Vector4& state() const { return x_; }
  const Matrix4& covariance() const { return P_; }
  Eigen::Vector2d position() const { return x_.head<2>(); }
  Eigen::Vector2d velocity() const { return x_.tail<2>(); }
  Eigen::Matrix2d positionCov() const { return P_.topLeftCorner<2, 2>(); }
  Eigen::Matrix2d velocityCov() const { return P_.bottomRightCorner<2, 2>(); }

 private:
  Vector4 x_ = Vector4::Zero();
  Matrix4 P_ = Matrix4::Identity();
};

}  // namespace polyloc
