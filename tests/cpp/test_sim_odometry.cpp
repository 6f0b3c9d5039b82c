// Odometry drift follows the alpha model (noise.hpp): variances linear in the distance and the
// rotation, accumulated over ticks, independent of the tick rate.
#include <polyloc/sim/odometry.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_odometry {

using namespace polyloc;


struct Final {
  double along = 0, lateral = 0, yaw = 0;
};

// Drives `length` metres straight along x and turns `turn` radians in place, at `rate` Hz.
Final drive(const OdometryNoise& n, uint64_t seed, double length, double turn, double rate) {
  OdometrySimulator odo(n, true, seed);
  odo.reset(Pose());
  const int steps = static_cast<int>(std::lround(10.0 * rate));  // 10 s of motion
  for (int k = 1; k <= steps; ++k) {
    const double f = static_cast<double>(k) / steps;
    odo.step(Pose::planar(length * f, 0, turn * f), 1.0 / rate);
  }
  return {odo.pose().x() - length, odo.pose().y(), angleDiff(odo.pose().yaw(), turn)};
}

struct Var {
  double n = 0, s = 0, s2 = 0;
  void add(double x) { ++n, s += x, s2 += x * x; }
  double mean() const { return s / n; }
  double var() const { return s2 / n - mean() * mean(); }
};


TEST(SimOdometry, StraightRunDriftFollowsAlphas) {
  OdometryNoise n;
  n.alpha1 = 0.0, n.alpha2 = 0.0003, n.alpha3 = 0.004, n.alpha4 = 0.0;  // small alpha2: heading errors shorten x only to second order
  const double L = 10.0;
  for (double rate : {50.0, 10.0}) {  // the same drift at any rate
    Var along, yaw;
    for (uint64_t seed = 1; seed <= 1500; ++seed) {
      const Final f = drive(n, seed, L, 0.0, rate);
      along.add(f.along);
      yaw.add(f.yaw);
    }
    EXPECT_NEAR(along.mean(), 0.0, 4 * std::sqrt(n.alpha3 * L / 1500));
    // Variance estimates from 1500 samples: relative error about sqrt(2 / 1500) = 3.7 %.
    EXPECT_NEAR(along.var(), n.alpha3 * L, 0.15 * n.alpha3 * L) << rate;
    EXPECT_NEAR(yaw.var(), n.alpha2 * L, 0.15 * n.alpha2 * L) << rate;
  }
}

TEST(SimOdometry, TurnInPlaceDriftFollowsAlphas) {
  OdometryNoise n;
  n.alpha1 = 0.003, n.alpha2 = 0.0, n.alpha3 = 0.0, n.alpha4 = 0.001;
  const double turn = 3.0;  // rad, within (-pi, pi] so the final yaw is unambiguous
  Var yaw, pos;
  for (uint64_t seed = 1; seed <= 1500; ++seed) {
    const Final f = drive(n, seed, 0.0, turn, 50.0);
    yaw.add(f.yaw);
    pos.add(f.along * f.along + f.lateral * f.lateral);
  }
  EXPECT_NEAR(yaw.var(), n.alpha1 * turn, 0.15 * n.alpha1 * turn);
  EXPECT_NEAR(pos.mean(), n.alpha4 * turn, 0.15 * n.alpha4 * turn);  // E|dp|^2 = alpha4 * rotation
}

TEST(SimOdometry, ExactWhenDisabledAndDeterministic) {
  OdometrySimulator exact(OdometryNoise{}, false, 1);
  exact.reset(Pose::planar(3, 4, 1.0));
  exact.step(Pose::planar(3 + std::cos(1.0), 4 + std::sin(1.0), 1.2), 0.02);
  EXPECT_NEAR(exact.pose().x(), 1.0, 1e-12);  // odom starts at the start pose: 1 m forward
  EXPECT_NEAR(exact.pose().y(), 0.0, 1e-12);
  EXPECT_NEAR(exact.pose().yaw(), 0.2, 1e-12);
  EXPECT_NEAR(exact.twist().x(), 50.0, 1e-9);
  EXPECT_NEAR(exact.twist().z(), 10.0, 1e-9);
  const Final a = drive(OdometryNoise{}, 5, 3.0, 1.0, 50), b = drive(OdometryNoise{}, 5, 3.0, 1.0, 50),
              c = drive(OdometryNoise{}, 6, 3.0, 1.0, 50);
  EXPECT_EQ(a.along, b.along);
  EXPECT_EQ(a.yaw, b.yaw);
  EXPECT_NE(a.along, c.along);
}

TEST(SimOdometry, UnevenFloorAddsSlipAndSlopeError) {
  // Up a 6 % ramp: the wheels measure the slope distance, odometry counts it as planar.
  OdometryNoise n;
  n.alpha1 = n.alpha2 = n.alpha3 = n.alpha4 = 0;
  n.slip_translation = n.slip_rotation = 0;
  OdometrySimulator odo(n, true, 1);
  const double pitch = -std::atan(0.06);
  odo.reset(Pose::fromXYZRPY(0, 0, 0, 0, pitch, 0));
  for (int k = 1; k <= 500; ++k) odo.step(Pose::fromXYZRPY(0.01 * k, 0, 0.0006 * k, 0, pitch, 0), 0.02);
  EXPECT_NEAR(odo.pose().x(), 5.0 * std::sqrt(1 + 0.06 * 0.06), 1e-9);
  // Rocking (roll/pitch changing) adds variance through the slip terms.
  n.slip_translation = 0.01;
  Var along;
  for (uint64_t seed = 1; seed <= 400; ++seed) {
    OdometrySimulator o(n, true, seed);
    o.reset(Pose());
    for (int k = 1; k <= 100; ++k) o.step(Pose::fromXYZRPY(0.01 * k, 0, 0, (k % 2) * 0.01, 0, 0), 0.02);
    along.add(o.pose().x() - 1.0);
  }
  EXPECT_NEAR(along.var(), 0.01 * 100 * 0.01, 0.25 * 0.01);  // slip_translation * total roll change
}

}  // namespace polyloc::t_sim_odometry
