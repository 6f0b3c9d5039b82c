#include <polyloc/sensors/sensor.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sensors {

using namespace polyloc;

void expectUnit(const BeamSet& b) {
  for (size_t i = 0; i < b.size(); ++i)
    ASSERT_NEAR(std::sqrt(b.dx[i] * b.dx[i] + b.dy[i] * b.dy[i] + b.dz[i] * b.dz[i]), 1.0, 1e-6) << i;
}

TEST(Sensors, PlanarPresets) {
  const BeamSet s300 = sickS300().beams();
  EXPECT_EQ(s300.size(), 541u);
  EXPECT_FLOAT_EQ(s300.range_max, 30.f);
  // First beam at -135 deg, last at +135 deg, middle straight ahead.
  EXPECT_NEAR(std::atan2(s300.dy.front(), s300.dx.front()), deg2rad(-135), 1e-6);
  EXPECT_NEAR(std::atan2(s300.dy.back(), s300.dx.back()), deg2rad(135), 1e-6);
  EXPECT_NEAR(s300.dx[270], 1.0, 1e-7);
  expectUnit(s300);
  EXPECT_EQ(hokuyoURG04LX().beams().size(), 667u);  // 240 / 0.36 + 1
  EXPECT_FLOAT_EQ(hokuyoURG04LX().beams().range_max, 4.f);
  EXPECT_EQ(sickLMS200().beams().size(), 361u);
  EXPECT_FLOAT_EQ(sickLMS200().beams().range_max, 8.f);
  for (float z : s300.dz) EXPECT_EQ(z, 0.f);
}

TEST(Sensors, Vlp16) {
  const LidarSpec spec = velodyneVLP16();
  const BeamSet b = spec.beams();
  EXPECT_EQ(b.size(), 16u * 1800u);
  expectUnit(b);
  EXPECT_NEAR(std::asin(b.dz.front()), deg2rad(-15), 1e-6);
  EXPECT_NEAR(std::asin(b.dz.back()), deg2rad(15), 1e-6);
  EXPECT_FLOAT_EQ(b.range_max, 100.f);
}

TEST(Sensors, PmdCamera) {
  const DepthCameraSpec cam = pmdO3D100();
  const BeamSet b = cam.beams();
  ASSERT_EQ(b.size(), 64u * 50u);
  expectUnit(b);
  EXPECT_FLOAT_EQ(b.range_max, 7.5f);
  // Top-left pixel looks up and left; the corner rays span the field of view.
  EXPECT_GT(b.dy[0], 0.f);
  EXPECT_GT(b.dz[0], 0.f);
  const size_t last = b.size() - 1;
  EXPECT_LT(b.dy[last], 0.f);
  EXPECT_LT(b.dz[last], 0.f);
  // Horizontal angle of the left edge of the first column is hfov/2.
  const double left_edge = std::atan((0 - cam.cx()) / cam.fx());
  EXPECT_NEAR(left_edge, -cam.hfov_rad / 2, 1e-9);
  // depth = range * factor: a wall 2 m ahead gives depth 2 for every pixel.
  const std::vector<float> f = cam.depthFactors();
  for (size_t i = 0; i < b.size(); ++i) EXPECT_NEAR((2.0 / b.dx[i]) * f[i], 2.0, 1e-5);
}

TEST(Sensors, MountedSensorAndPresets) {
  Sensor s{"front", sensorPreset("sick_s300"), Pose::fromXYZRPY(0.3, 0, 0.1, 0, 0, 0)};
  EXPECT_STREQ(s.typeName(), "planar_scanner");
  EXPECT_DOUBLE_EQ(s.rateHz(), 12.5);
  const Pose w = s.worldPose(Pose::planar(1, 1, M_PI / 2));
  EXPECT_NEAR(w.x(), 1.0, 1e-12);
  EXPECT_NEAR(w.y(), 1.3, 1e-12);
  EXPECT_NEAR(w.z(), 0.1, 1e-12);
  EXPECT_STREQ((Sensor{"c", sensorPreset("pmd_o3d100"), {}}.typeName()), "depth_camera");
  EXPECT_STREQ((Sensor{"l", sensorPreset("vlp16"), {}}.typeName()), "lidar");
  try {
    sensorPreset("sick_s3000");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sick_s3000"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("hokuyo_urg04lx"), std::string::npos);
  }
}

}  // namespace polyloc::t_sensors
