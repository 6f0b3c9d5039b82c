#include <polyloc/geometry/pose.hpp>
#include <polyloc/geometry/random.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_pose {

using namespace polyloc;

TEST(Pose, EulerRoundTrip) {
  const Pose p = Pose::fromXYZRPY(1, 2, 3, 0.1, -0.2, 2.5);
  EXPECT_NEAR(p.roll(), 0.1, 1e-12);
  EXPECT_NEAR(p.pitch(), -0.2, 1e-12);
  EXPECT_NEAR(p.yaw(), 2.5, 1e-12);
  EXPECT_DOUBLE_EQ(p.z(), 3.0);
}

TEST(Pose, ComposeAppliesChildFirst) {
  // base 2 m along x facing +y; sensor 1 m forward on the base => sensor at (2, 1).
  const Pose map_T_base = Pose::planar(2, 0, M_PI / 2);
  const Pose base_T_sensor = Pose::planar(1, 0, 0);
  const Pose map_T_sensor = map_T_base * base_T_sensor;
  EXPECT_NEAR(map_T_sensor.x(), 2.0, 1e-12);
  EXPECT_NEAR(map_T_sensor.y(), 1.0, 1e-12);
  EXPECT_NEAR(map_T_sensor.yaw(), M_PI / 2, 1e-12);
  const Eigen::Vector3d p = map_T_base * Eigen::Vector3d(1, 0, 0);
  EXPECT_TRUE(p.isApprox(Eigen::Vector3d(2, 1, 0), 1e-12));
}

TEST(Pose, InverseUndoes) {
  const Pose p = Pose::fromXYZRPY(0.3, -1, 2, 0.4, 0.2, -1.3);
  EXPECT_TRUE((p * p.inverse()).isApprox(Pose(), 1e-12));
  EXPECT_TRUE((p.inverse() * p).isApprox(Pose(), 1e-12));
  const Eigen::Vector3d x(1, 2, 3);
  EXPECT_TRUE((p.inverse() * (p * x)).isApprox(x, 1e-12));
  EXPECT_TRUE(Pose::fromMatrix(p.matrix()).isApprox(p, 1e-12));
}

TEST(Pose, InterpolateEndsAndMiddle) {
  const Pose a = Pose::fromXYZRPY(0, 0, 0, 0, 0, 0.2);
  const Pose b = Pose::fromXYZRPY(2, 4, 1, 0, 0, 1.2);
  EXPECT_TRUE(Pose::interpolate(a, b, 0).isApprox(a, 1e-12));
  EXPECT_TRUE(Pose::interpolate(a, b, 1).isApprox(b, 1e-12));
  const Pose m = Pose::interpolate(a, b, 0.5);
  EXPECT_NEAR(m.x(), 1.0, 1e-12);
  EXPECT_NEAR(m.y(), 2.0, 1e-12);
  EXPECT_NEAR(m.yaw(), 0.7, 1e-12);  // slerp about one axis is linear in angle
}

TEST(Pose, PlanarProjectionDropsHeightRollPitch) {
  const Pose p = Pose::fromXYZRPY(1, 2, 0.3, 0.05, -0.04, 1.0).planarProjection();
  EXPECT_DOUBLE_EQ(p.z(), 0.0);
  EXPECT_NEAR(p.roll(), 0.0, 1e-12);
  EXPECT_NEAR(p.pitch(), 0.0, 1e-12);
  EXPECT_NEAR(p.yaw(), 1.0, 1e-12);
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
}

TEST(Pose, WrapAngle) {
  EXPECT_NEAR(wrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrapAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(angleDiff(0.1, 2 * M_PI - 0.1), 0.2, 1e-12);
}

TEST(CounterRng, PureFunctionOfCounters) {
  const CounterRng rng(42);
  EXPECT_EQ(rng.bits(3, 7, 1), CounterRng(42).bits(3, 7, 1));
  EXPECT_NE(rng.bits(3, 7, 1), rng.bits(3, 8, 1));
  EXPECT_NE(rng.bits(3, 7, 1), CounterRng(43).bits(3, 7, 1));
  double sum = 0, sum2 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double z = rng.normal(0, i);
    sum += z;
    sum2 += z * z;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sum2 / n, 1.0, 0.02);
}

}  // namespace polyloc::t_pose
