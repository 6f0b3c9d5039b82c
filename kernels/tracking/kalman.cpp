#include <polyloc/tracking/kalman.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace polyloc {

Ellipse covarianceEllipse(const Eigen::Matrix2d& cov, double sigmas) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (cov + cov.transpose()));
  const Eigen::Vector2d l = es.eigenvalues().cwiseMax(0.0);  // ascending
  const Eigen::Vector2d major = es.eigenvectors().col(1);
  Ellipse e;
  e.major = sigmas * std::sqrt(l(1));
  e.minor = sigmas * std::sqrt(l(0));
  double a = std::atan2(major.y(), major.x());
  if (a > M_PI / 2) a -= M_PI;
  if (a <= -M_PI / 2) a += M_PI;
  e.angle = a;
  return e;
}

ConstantVelocityKalman ConstantVelocityKalman::start(const Eigen::Vector2d& position, const Eigen::Matrix2d& cov,
                                                     double speed_sigma) {
  Vector4 x = Vector4::Zero();
  x.head<2>() = position;
  Matrix4 P = Matrix4::Zero();
  P.topLeftCorner<2, 2>() = cov;
  P.bottomRightCorner<2, 2>() = Eigen::Matrix2d::Identity() * speed_sigma * speed_sigma;
  return {x, P};
}

void ConstantVelocityKalman::predict(double dt, double acceleration_sigma) {
  if (!(dt > 0)) return;
  Matrix4 F = Matrix4::Identity();
  F(0, 2) = F(1, 3) = dt;
  // Acceleration constant over the step: G = (dt^2/2, dt) per axis, Q = G G' sigma^2.
  const double q = acceleration_sigma * acceleration_sigma;
  const double q11 = q * dt * dt * dt * dt / 4, q12 = q * dt * dt * dt / 2, q22 = q * dt * dt;
  Matrix4 Q = Matrix4::Zero();
  Q(0, 0) = Q(1, 1) = q11;
  Q(0, 2) = Q(2, 0) = Q(1, 3) = Q(3, 1) = q12;
  Q(2, 2) = Q(3, 3) = q22;
  x_ = F * x_;
  P_ = F * P_ * F.transpose() + Q;
}

Eigen::Matrix2d ConstantVelocityKalman::innovation(const Eigen::Matrix2d& R) const {
  return P_.topLeftCorner<2, 2>() + R;
}

double ConstantVelocityKalman::mahalanobis2(const Eigen::Vector2d& z, const Eigen::Matrix2d& R) const {
  const Eigen::Vector2d y = z - position();
  return y.dot(innovation(R).ldlt().solve(y));
}

void ConstantVelocityKalman::update(const Eigen::Vector2d& z, const Eigen::Matrix2d& R) {
  const Eigen::Matrix2d S = innovation(R);
  // K = P H' S^-1 with H = [I 0]: the first two columns of P.
  const Eigen::Matrix<double, 4, 2> PHt = P_.leftCols<2>();
  const Eigen::Matrix<double, 4, 2> K = S.ldlt().solve(PHt.transpose()).transpose();
  x_ += K * (z - position());
  Eigen::Matrix<double, 4, 4> IKH = Matrix4::Identity();
  IKH.leftCols<2>() -= K;
  P_ = IKH * P_ * IKH.transpose() + K * R * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
}

void ConstantVelocityKalman::clampSpeed(double max_speed) {
  const double s = x_.tail<2>().norm();
  if (s > max_speed && s > 0) x_.tail<2>() *= max_speed / s;
}

}  // namespace polyloc
