// The constant-velocity Kalman filter against values computed by hand, and covariance ellipses.
#include <polyloc/tracking/kalman.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_kalman {

using namespace polyloc;

TEST(TrackingKalman, PredictWithoutNoiseMovesAndSpreads) {
  ConstantVelocityKalman kf(Eigen::Vector4d(1, 2, 0.5, -1), Eigen::Matrix4d::Identity());
  kf.predict(2.0, 0.0);
  EXPECT_TRUE(kf.position().isApprox(Eigen::Vector2d(2, 0)));
  // F P F' with P = I, dt = 2, per axis: [[1 + dt^2, dt], [dt, 1]] = [[5, 2], [2, 1]].
  EXPECT_DOUBLE_EQ(kf.covariance()(0, 0), 5.0);
  EXPECT_DOUBLE_EQ(kf.covariance()(0, 2), 2.0);
  EXPECT_DOUBLE_EQ(kf.covariance()(2, 2), 1.0);
  EXPECT_DOUBLE_EQ(kf.covariance()(0, 1), 0.0);  // axes independent
}

TEST(TrackingKalman, PredictAddsWhiteAccelerationNoise) {
  ConstantVelocityKalman kf(Eigen::Vector4d::Zero(), Eigen::Matrix4d::Zero());
  kf.predict(1.0, 2.0);  // q = 4: Q = q [[dt^4/4, dt^3/2], [dt^3/2, dt^2]] = [[1, 2], [2, 4]]
  EXPECT_DOUBLE_EQ(kf.covariance()(1, 1), 1.0);
  EXPECT_DOUBLE_EQ(kf.covariance()(1, 3), 2.0);
  EXPECT_DOUBLE_EQ(kf.covariance()(3, 3), 4.0);
  kf.predict(0.0, 2.0);  // no time, no change
  EXPECT_DOUBLE_EQ(kf.covariance()(3, 3), 4.0);
}

TEST(TrackingKalman, UpdateMatchesHandComputedGain) {
  // Per axis P = [[2, 1], [1, 1]] (after one step from I), R = 1: S = 3, K = [2/3, 1/3].
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = P(1, 1) = 2, P(0, 2) = P(2, 0) = P(1, 3) = P(3, 1) = 1, P(2, 2) = P(3, 3) = 1;
  ConstantVelocityKalman kf(Eigen::Vector4d(0, 0, 1, 0), P);
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
  EXPECT_NEAR(kf.mahalanobis2(Eigen::Vector2d(3, 0), R), 3.0, 1e-12);  // 3^2 / S
  kf.update(Eigen::Vector2d(3, 0), R);
  EXPECT_NEAR(kf.position().x(), 2.0, 1e-12);   // 0 + 2/3 * 3
  EXPECT_NEAR(kf.velocity().x(), 2.0, 1e-12);   // 1 + 1/3 * 3
  EXPECT_NEAR(kf.position().y(), 0.0, 1e-12);
  // (I - K H) P: P00 = 2 - 2/3 * 2 = 2/3, P02 = 1 - 2/3 = 1/3, P22 = 1 - 1/3 = 2/3.
  EXPECT_NEAR(kf.covariance()(0, 0), 2.0 / 3, 1e-12);
  EXPECT_NEAR(kf.covariance()(0, 2), 1.0 / 3, 1e-12);
  EXPECT_NEAR(kf.covariance()(2, 2), 2.0 / 3, 1e-12);
}

TEST(TrackingKalman, StartClampAndEllipse) {
  Eigen::Matrix2d cov;
  cov << 0.04, 0, 0, 0.01;
  ConstantVelocityKalman kf = ConstantVelocityKalman::start({1, 1}, cov, 0.5);
  EXPECT_TRUE(kf.velocity().isZero());
  EXPECT_DOUBLE_EQ(kf.velocityCov()(0, 0), 0.25);
  kf = ConstantVelocityKalman(Eigen::Vector4d(0, 0, 3, 4), Eigen::Matrix4d::Identity());
  kf.clampSpeed(2.5);
  EXPECT_NEAR(kf.velocity().norm(), 2.5, 1e-12);
  EXPECT_NEAR(kf.velocity().x(), 1.5, 1e-12);

  Ellipse e = covarianceEllipse(cov, 2.0);
  EXPECT_NEAR(e.major, 0.4, 1e-12);
  EXPECT_NEAR(e.minor, 0.2, 1e-12);
  EXPECT_NEAR(e.angle, 0.0, 1e-12);
  // Rotated by 30 deg: the major axis along 30 deg.
  const double a = M_PI / 6;
  Eigen::Matrix2d Rot;
  Rot << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  e = covarianceEllipse(Rot * cov * Rot.transpose());
  EXPECT_NEAR(e.major, 0.2, 1e-12);
  EXPECT_NEAR(e.angle, a, 1e-9);
}

}  // namespace polyloc::t_tracking_kalman
