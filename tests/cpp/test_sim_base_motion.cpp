#include <polyloc/sim/base_motion.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_base_motion {

using namespace polyloc;


constexpr int64_t kSec = 1000000000;

// A controller sending (vx, vy, wz) every `period` until `until` (the last step may be shorter).
void drive(BaseMotion& b, double vx, double vy, double wz, int64_t until, int64_t period = kSec / 10) {
  while (b.now() < until) {
    ASSERT_TRUE(b.command({b.now(), vx, vy, wz}));
    b.advance(std::min(until, b.now() + period));
  }
}

BaseMotion differential(const Pose& start = Pose()) { return BaseMotion(Kinematics::Differential, {}, start, 0); }


TEST(SimBaseMotion, RampsUpWithinTheAccelerationLimitThenCruises) {
  BaseMotion b = differential();
  drive(b, 0.5, 0, 0, 4 * kSec / 10);
  EXPECT_NEAR(b.velocity().vx, 0.4, 1e-12);  // 1 m/s^2 for 0.4 s
  drive(b, 0.5, 0, 0, 5 * kSec / 10);
  EXPECT_NEAR(b.velocity().vx, 0.5, 1e-12);
  drive(b, 0.5, 0, 0, 2 * kSec);
  // 0.125 m while speeding up (v^2 / 2a), then 1.5 s at 0.5 m/s.
  EXPECT_NEAR(b.pose().x(), 0.125 + 0.75, 1e-9);
  EXPECT_NEAR(b.pose().y(), 0.0, 1e-12);
  EXPECT_NEAR(b.pose().yaw(), 0.0, 1e-12);
  EXPECT_EQ(b.counters().accepted, 20u);
  EXPECT_EQ(b.counters().clamped, 0u);
  EXPECT_FALSE(b.commandTimedOut());
}

TEST(SimBaseMotion, ConstantTwistTracesACircle) {
  const double v = 0.4, w = 0.8, r = v / w;
  BaseMotion b = differential(Pose::planar(1, -2, 0.3));
  drive(b, v, 0, w, kSec);  // at speed after 0.4 s
  const Pose p0 = b.pose();
  const int64_t t0 = b.now(), turn = std::llround(2 * M_PI / w * 1e9);
  drive(b, v, 0, w, t0 + turn / 2);
  EXPECT_NEAR((b.pose().translation() - p0.translation()).norm(), 2 * r, 1e-6);  // the far side
  EXPECT_NEAR(std::abs(angleDiff(b.pose().yaw(), p0.yaw())), M_PI, 1e-6);
  drive(b, v, 0, w, t0 + turn);
  EXPECT_NEAR(b.pose().x(), p0.x(), 1e-6);
  EXPECT_NEAR(b.pose().y(), p0.y(), 1e-6);
  EXPECT_NEAR(angleDiff(b.pose().yaw(), p0.yaw()), 0.0, 1e-6);
  EXPECT_EQ(b.pose().z(), 0.0);
}

TEST(SimBaseMotion, WatchdogBrakesToAStopWhenCommandsCease) {
  BaseMotion b = differential();
  drive(b, 0.5, 0, 0, 2 * kSec);  // last command at 1.9 s
  const double x0 = b.pose().x();
  b.advance(2 * kSec + 3 * kSec / 10);  // 0.4 s after the last command: still going
  EXPECT_FALSE(b.commandTimedOut());
  EXPECT_NEAR(b.velocity().vx, 0.5, 1e-12);
  b.advance(2 * kSec + 65 * kSec / 100);  // timeout at 2.4 s, braking for 0.25 s since
  EXPECT_TRUE(b.commandTimedOut());
  EXPECT_NEAR(b.velocity().vx, 0.25, 1e-12);
  b.advance(10 * kSec);
  EXPECT_EQ(b.velocity().vx, 0.0);
  // 0.5 s at 0.5 m/s until the timeout, then v^2 / (2 a) while braking.
  EXPECT_NEAR(b.pose().x() - x0, 0.2 + 0.5 * 0.5 / 2, 1e-9);
  EXPECT_EQ(b.counters().timeouts, 1u);
  ASSERT_TRUE(b.command({b.now(), 0.2, 0, 0}));  // a new command lifts the stop
  EXPECT_FALSE(b.commandTimedOut());
}

TEST(SimBaseMotion, OmniMovesSideways) {
  BaseMotion b(Kinematics::Omni, {}, Pose::planar(0, 0, M_PI / 2), 0);
  drive(b, 0, 0.3, 0, 2 * kSec);
  // Base +y is map -x when facing +y: 0.045 m speeding up, then 1.7 s at 0.3 m/s.
  EXPECT_NEAR(b.pose().x(), -(0.045 + 0.51), 1e-9);
  EXPECT_NEAR(b.pose().y(), 0.0, 1e-9);
  EXPECT_NEAR(b.velocity().vy, 0.3, 1e-12);
  EXPECT_EQ(b.counters().lateral_on_differential, 0u);
}

TEST(SimBaseMotion, DifferentialIgnoresLateralAndCountsIt) {
  BaseMotion b = differential();
  drive(b, 0, 0.3, 0, kSec);
  EXPECT_EQ(b.pose().x(), 0.0);
  EXPECT_EQ(b.pose().y(), 0.0);
  EXPECT_EQ(b.velocity().vy, 0.0);
  EXPECT_EQ(b.counters().lateral_on_differential, 10u);
  EXPECT_EQ(b.counters().accepted, 10u);
}

TEST(SimBaseMotion, RejectsNonsenseNamingTheField) {
  BaseMotion b = differential();
  std::string why;
  EXPECT_FALSE(b.command({0, std::numeric_limits<double>::quiet_NaN(), 0, 0}, &why));
  EXPECT_NE(why.find("vx"), std::string::npos) << why;
  EXPECT_FALSE(b.command({0, 0, std::numeric_limits<double>::infinity(), 0}, &why));
  EXPECT_NE(why.find("vy"), std::string::npos) << why;
  EXPECT_FALSE(b.command({0, 0, 0, 1e19}, &why));
  EXPECT_NE(why.find("wz = 1e+19"), std::string::npos) << why;
  EXPECT_FALSE(b.command({2 * kSec, 0.1, 0, 0}, &why));  // 2 s ahead of the base clock
  EXPECT_NE(why.find("stamp_ns"), std::string::npos) << why;
  ASSERT_TRUE(b.command({kSec / 2, 0.3, 0, 0}, &why));  // 0.5 s ahead: fine
  EXPECT_FALSE(b.command({kSec / 4, 0.1, 0, 0}, &why));  // older than the accepted one
  EXPECT_NE(why.find("stamp_ns = 250000000"), std::string::npos) << why;
  EXPECT_EQ(b.counters().rejected, 5u);
  EXPECT_EQ(b.counters().accepted, 1u);
  b.advance(4 * kSec / 10);  // the rejected commands changed nothing: the target is still 0.3
  EXPECT_NEAR(b.velocity().vx, 0.3, 1e-12);
}

TEST(SimBaseMotion, ClampsToTheLimits) {
  BaseMotion b = differential();
  drive(b, 5.0, 0, -10.0, 3 * kSec);
  EXPECT_EQ(b.velocity().vx, 0.8);
  EXPECT_EQ(b.velocity().wz, -1.5);
  EXPECT_EQ(b.counters().clamped, 30u);
  EXPECT_EQ(b.counters().rejected, 0u);
}

TEST(SimBaseMotion, TimeGoingBackwardsIsIgnoredAndCounted) {
  BaseMotion b = differential();
  drive(b, 0.5, 0, 0, kSec);
  const Pose p = b.pose();
  b.advance(kSec / 2);
  EXPECT_EQ(b.now(), kSec);
  EXPECT_EQ(b.pose().x(), p.x());
  EXPECT_EQ(b.pose().yaw(), p.yaw());
  EXPECT_EQ(b.counters().time_backwards, 1u);
}

TEST(SimBaseMotion, StopHaltsAtOnceUntilTheNextCommand) {
  BaseMotion b = differential();
  drive(b, 0.5, 0, 0.2, kSec);
  b.stop();
  EXPECT_EQ(b.velocity().vx, 0.0);
  EXPECT_EQ(b.velocity().wz, 0.0);
  const Pose p = b.pose();
  b.advance(b.now() + kSec / 5);  // within the timeout, yet the target stays zero
  EXPECT_EQ(b.pose().x(), p.x());
  EXPECT_EQ(b.pose().y(), p.y());
  EXPECT_EQ(b.pose().yaw(), p.yaw());
  drive(b, 0.5, 0, 0, b.now() + kSec / 10);
  EXPECT_NEAR(b.velocity().vx, 0.1, 1e-12);
}

TEST(SimBaseMotion, BadLimitsThrowNamingTheField) {
  BaseLimits l;
  l.max_acc = 0;
  try {
    const BaseMotion b(Kinematics::Omni, l, Pose(), 0);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_acc"), std::string::npos) << e.what();
  }
}

}  // namespace polyloc::t_sim_base_motion
