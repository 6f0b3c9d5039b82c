#include <polyloc/mcl/odometry_noise.hpp>
#include <polyloc/mcl/pose_covariance.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace polyloc {
namespace {
constexpr int kPlanar[3] = {0, 1, 5};  // x, y, yaw in x y z roll pitch yaw
}

Eigen::Matrix3d planarCovariance(const Eigen::Matrix<double, 6, 6>& c) {
  Eigen::Matrix3d m;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m(a, b) = c(kPlanar[a], kPlanar[b]);
  return m;
}

void setPlanarCovariance(Eigen::Matrix<double, 6, 6>& c, const Eigen::Matrix3d& m) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) c(kPlanar[a], kPlanar[b]) = m(a, b);
}

double maxPositionStd(const Eigen::Matrix3d& cov) {
  const Eigen::Matrix2d p = cov.topLeftCorner<2, 2>();
  return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(p).eigenvalues().maxCoeff()));
}

void PoseCovariance::restart(const Eigen::Matrix3d& cov) {
  cov_ = cov;
  valid_ = cov.allFinite();
}

double PoseCovariance::update(const Pose& pose, const Pose& delta, const MotionNoise& noise, const Pose& now,
                              const Eigen::Matrix3d* fit, const Eigen::Vector3d& floor) {
  const Eigen::Matrix3d prior = propagateCovariance(cov_, pose, delta, noise);
  double nis = 0;
  if (fit) {
    const Eigen::Matrix3d R = *fit + Eigen::Vector3d(1e-8, 1e-8, 1e-10).asDiagonal().toDenseMatrix();
    const Pose predicted = pose.planarProjection() * delta.planarProjection();
    const Pose d = predicted.inverse() * now.planarProjection();
    const double c = std::cos(predicted.yaw()), s = std::sin(predicted.yaw());
    const Eigen::Vector3d e(c * d.x() - s * d.y(), s * d.x() + c * d.y(), d.yaw());  // map frame
    const Eigen::Matrix3d S = prior + R + floor.cwiseAbs2().asDiagonal().toDenseMatrix();
    nis = e.dot(S.ldlt().solve(e));
    cov_ = (prior.inverse() + R.inverse()).inverse();
  } else {
    cov_ = prior;
  }
  valid_ = cov_.allFinite();
  return nis;
}

}  // namespace polyloc
