// polynav's reading of polylocd (polynav/polylocd_link.hpp): a VRS slot shorter than its header
// or than the ranges its count claims is refused with the sizes named, never copied beyond; a
// failed pose read gives the identity pose, not localised; the pose now is map_T_odom after odom.
#include <polynav/polylocd_link.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace polyloc::t_nav_link {

using namespace polynav;

std::vector<char> vrsSlot(uint32_t count_claimed, size_t ranges_held) {
  std::vector<char> slot(offsetof(polyloc_vrs, ranges) + ranges_held * sizeof(float));
  polyloc_vrs v{};
  v.stamp_ns = 1'700'000'000'000'000'000;
  v.angle_min = -float(M_PI);
  v.angle_increment = 0.5f;
  v.range_max = 8.0f;
  v.count = count_claimed;
  std::memcpy(slot.data(), &v, offsetof(polyloc_vrs, ranges));
  for (size_t k = 0; k < ranges_held; ++k) {
    const float r = 1.0f + float(k);
    std::memcpy(slot.data() + offsetof(polyloc_vrs, ranges) + k * sizeof(float), &r, sizeof r);
  }
  return slot;
}

TEST(NavLink, VrsSlotDecodesToSegmentCentres) {
  const std::vector<char> slot = vrsSlot(3, 3);
  std::string why;
  const auto f = decodeVrs(slot.data(), slot.size(), &why);
  ASSERT_TRUE(f) << why;
  EXPECT_EQ(f->stamp_ns, 1'700'000'000'000'000'000);
  EXPECT_NEAR(f->scan.angle_min, -M_PI + 0.25, 1e-6);
  EXPECT_FLOAT_EQ(f->scan.angle_increment, 0.5f);
  EXPECT_FLOAT_EQ(f->scan.range_max, 8.0f);
  EXPECT_EQ(f->scan.ranges, (std::vector<float>{1, 2, 3}));
}

TEST(NavLink, VrsSlotShorterThanItsCountIsRefused) {
  std::string why;
  const std::vector<char> lying = vrsSlot(1000, 3);  // claims 1,000 ranges, holds 3
  EXPECT_FALSE(decodeVrs(lying.data(), lying.size(), &why));
  EXPECT_NE(why.find("claims 1000 ranges"), std::string::npos) << why;
  EXPECT_NE(why.find(std::to_string(lying.size()) + " bytes"), std::string::npos) << why;
  const std::vector<char> one_short = vrsSlot(4, 3);
  EXPECT_FALSE(decodeVrs(one_short.data(), one_short.size(), &why));
  const std::vector<char> huge = vrsSlot(0xFFFFFFFFu, 3);
  EXPECT_FALSE(decodeVrs(huge.data(), huge.size(), &why));
  const std::vector<char> head = vrsSlot(0, 0);
  EXPECT_FALSE(decodeVrs(head.data(), head.size() - 1, &why));
  EXPECT_NE(why.find("shorter than its"), std::string::npos) << why;
  EXPECT_FALSE(decodeVrs(nullptr, 0, &why));
  const auto empty = decodeVrs(head.data(), head.size(), &why);  // no ranges at all is a frame
  ASSERT_TRUE(empty);
  EXPECT_TRUE(empty->scan.ranges.empty());
}

TEST(NavLink, FailedPoseReadIsTheIdentityNotLocalised) {
  const PoseRead r = readPoseNow(nullptr, -1);  // no client: the read fails
  EXPECT_FALSE(r.localised);
  EXPECT_EQ(r.pose, Eigen::Vector3d(0, 0, 0));
  const PoseRead o = readPoseNow(nullptr, 3);  // nor can odometry be read
  EXPECT_FALSE(o.localised);
  EXPECT_EQ(o.pose, Eigen::Vector3d(0, 0, 0));
}

TEST(NavLink, PoseNowIsMapOdomAfterOdometry) {
  polyloc_pose p{};
  p.x = 9, p.y = 9, p.qw = 1;  // polylocd's own pose: used only without odometry
  const double h = M_PI / 4;   // map_T_odom: (2, 1), yaw 90 deg
  p.map_odom[0] = 2, p.map_odom[1] = 1, p.map_odom[3] = std::cos(h), p.map_odom[6] = std::sin(h);
  polyloc_odometry odom{};
  odom.x = 1, odom.y = 0.5, odom.qw = std::cos(h / 2), odom.qz = std::sin(h / 2);  // yaw 45 deg
  const Eigen::Vector3d now = poseNow(p, &odom);
  EXPECT_NEAR(now.x(), 2 - 0.5, 1e-12);
  EXPECT_NEAR(now.y(), 1 + 1, 1e-12);
  EXPECT_NEAR(now.z(), 3 * M_PI / 4, 1e-12);
  const Eigen::Vector3d own = poseNow(p, nullptr);
  EXPECT_EQ(own, Eigen::Vector3d(9, 9, 0));
}

// Stamps are the writer's word: the controller's clock and the stop's stamp never wrap.
TEST(NavLink, StampsFarApartDoNotWrap) {
  constexpr int64_t lo = std::numeric_limits<int64_t>::min() + 1, hi = std::numeric_limits<int64_t>::max();
  EXPECT_NEAR(secondsBetween(lo, hi), 1.8446744e10, 1e4);  // int64 subtraction would overflow
  EXPECT_NEAR(secondsBetween(hi, lo), -1.8446744e10, 1e4);
  EXPECT_DOUBLE_EQ(secondsBetween(1'700'000'000'000'000'000, 1'700'000'001'500'000'000), 1.5);
  EXPECT_EQ(stopStamp(hi, 5), hi);
  EXPECT_EQ(stopStamp(1'000, 5), 1'001);
  EXPECT_EQ(stopStamp(0, 5), 5);  // no command went out: the wall clock
  EXPECT_EQ(stopStamp(-7, 5), 5);
}

}  // namespace polyloc::t_nav_link
