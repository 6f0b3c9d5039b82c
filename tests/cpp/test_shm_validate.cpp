// validateInput on malformed frames: each gives its Reject and a message naming channel and frame.
#include "shm/validate.hpp"
#include "shm_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace polyloc::t_shm_validate {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using shm::Reject;

constexpr int64_t kNow = 1'700'000'000'000'000'000;

polyloc_channel_desc desc(const char* name, uint32_t kind, uint32_t count, uint32_t w = 0, uint32_t h = 0) {
  shm::ChannelSpec s = test::spec(name, kind, POLYLOC_DIR_INPUT, 4, count, w, h);
  polyloc_channel_desc d{};
  std::snprintf(d.name, sizeof d.name, "%s", name);
  d.kind = kind;
  d.count = count;
  d.width = w;
  d.height = h;
  d.payload_max = shm::payloadSize(s);
  return d;
}

std::vector<uint8_t> scan(uint32_t count, int64_t stamp, float value = 2.f) {
  std::vector<uint8_t> b(offsetof(polyloc_ranges, ranges) + count * sizeof(float));
  auto* p = reinterpret_cast<polyloc_ranges*>(b.data());
  p->stamp_ns = stamp;
  p->count = count;
  for (uint32_t i = 0; i < count; ++i) p->ranges[i] = value;
  return b;
}

polyloc_odometry odometry(int64_t stamp) {
  polyloc_odometry o{};
  o.stamp_ns = stamp;
  o.qw = 1;
  return o;
}

shm::StampRules rules(int64_t last = INT64_MIN) {
  shm::StampRules r;
  r.now_ns = kNow;
  r.last_ns = last;
  return r;
}

void expectReject(const shm::Validation& v, Reject r, const std::string& part) {
  EXPECT_EQ(v.reject, r) << v.why;
  EXPECT_FALSE(v);
  EXPECT_NE(v.why.find(part), std::string::npos) << v.why;
}

TEST(ShmValidate, GoodFramesPass) {
  const auto d = desc("scan/front", POLYLOC_KIND_RANGES, 270);
  auto b = scan(270, kNow - 1000);
  reinterpret_cast<polyloc_ranges*>(b.data())->ranges[3] = NAN;   // one beam without return is normal
  const auto v = shm::validateInput(d, 5, b.data(), b.size(), rules());
  EXPECT_TRUE(v) << v.why;
  EXPECT_STREQ(shm::toString(v.reject), "ok");
  const auto o = odometry(kNow);
  EXPECT_TRUE(shm::validateInput(desc("odom", POLYLOC_KIND_ODOMETRY, 0), 1, reinterpret_cast<const uint8_t*>(&o),
                                 sizeof o, rules()));
}

TEST(ShmValidate, WrongSize) {
  const auto d = desc("scan/front", POLYLOC_KIND_RANGES, 270);
  auto b = scan(270, kNow);
  expectReject(shm::validateInput(d, 123, b.data(), 540, rules()), Reject::Size,
               "scan/front frame 123: 540 bytes, expected 1096 for 270 beams");
  auto wrong = scan(100, kNow);
  expectReject(shm::validateInput(d, 124, wrong.data(), wrong.size(), rules()), Reject::Size,
               "scan/front frame 124: count 100, expected 270 beams");
  expectReject(shm::validateInput(d, 125, b.data(), 8, rules()), Reject::Size, "scan/front frame 125: 8 bytes, less than");
  const auto o = odometry(kNow);
  expectReject(shm::validateInput(desc("odom", POLYLOC_KIND_ODOMETRY, 0), 9, reinterpret_cast<const uint8_t*>(&o), 80,
                                  rules()),
               Reject::Size, "odom frame 9: 80 bytes, expected 88 for odometry");
  EXPECT_STREQ(shm::toString(Reject::Size), "size");
}

TEST(ShmValidate, HugeSizeFieldIsRefusedBeforeAnyRead) {
  const auto d = desc("scan/front", POLYLOC_KIND_RANGES, 270);
  uint8_t small[16] = {};
  expectReject(shm::validateInput(d, 7, small, 0xffffffffu, rules()), Reject::Size,
               "scan/front frame 7: size field 4294967295 bytes exceeds the channel's capacity of 1096");
}

TEST(ShmValidate, NaNOdometryAndAllNaNScan) {
  auto o = odometry(kNow);
  o.y = std::numeric_limits<double>::quiet_NaN();
  const auto od = desc("odom", POLYLOC_KIND_ODOMETRY, 0);
  expectReject(shm::validateInput(od, 42, reinterpret_cast<const uint8_t*>(&o), sizeof o, rules()), Reject::NaN,
               "odom frame 42: y is nan");
  o = odometry(kNow);
  o.qw = 0.5;
  expectReject(shm::validateInput(od, 43, reinterpret_cast<const uint8_t*>(&o), sizeof o, rules()), Reject::NaN,
               "odom frame 43: quaternion norm 0.5");
  const auto d = desc("scan/front", POLYLOC_KIND_RANGES, 270);
  auto b = scan(270, kNow, NAN);
  expectReject(shm::validateInput(d, 44, b.data(), b.size(), rules()), Reject::NaN,
               "scan/front frame 44: none of the 270 ranges is a distance");
  b = scan(270, kNow, 1e19f);  // finite, but no distance a scanner measures
  expectReject(shm::validateInput(d, 45, b.data(), b.size(), rules()), Reject::NaN, "beyond 10000 m");
  o.qw = 1;
  o.x = 1e19;
  expectReject(shm::validateInput(od, 46, reinterpret_cast<const uint8_t*>(&o), sizeof o, rules()), Reject::NaN,
               "odom frame 46: x is 10000000000000000000");
  EXPECT_STREQ(shm::toString(Reject::NaN), "nan");
}

TEST(ShmValidate, StaleAndFutureStamps) {
  const auto d = desc("scan/front", POLYLOC_KIND_RANGES, 4);
  auto old = scan(4, kNow - 600'000'000);
  expectReject(shm::validateInput(d, 10, old.data(), old.size(), rules()), Reject::Stale,
               "scan/front frame 10: stamp");
  auto repeat = scan(4, kNow - 1000);
  expectReject(shm::validateInput(d, 11, repeat.data(), repeat.size(), rules(kNow - 1000)), Reject::Stale,
               "is not after the last frame's");
  auto future = scan(4, kNow + 200'000'000);
  expectReject(shm::validateInput(d, 12, future.data(), future.size(), rules()), Reject::Future,
               "scan/front frame 12: stamp");
  auto extreme = scan(4, INT64_MAX);
  expectReject(shm::validateInput(d, 13, extreme.data(), extreme.size(), rules()), Reject::Future, "in the future");
  auto r = rules();
  r.max_age_ns = -1;   // checks switched off
  r.max_future_ns = -1;
  EXPECT_TRUE(shm::validateInput(d, 14, old.data(), old.size(), r));
  EXPECT_STREQ(shm::toString(Reject::Stale), "stale");
  EXPECT_STREQ(shm::toString(Reject::Future), "future");
}

TEST(ShmValidate, DepthFrames) {
  const auto d = desc("depth/tof", POLYLOC_KIND_DEPTH, 0, 4, 3);
  std::vector<uint8_t> b(offsetof(polyloc_depth, data) + 2 * 12 * sizeof(float));
  auto* p = reinterpret_cast<polyloc_depth*>(b.data());
  p->stamp_ns = kNow;
  p->width = 4;
  p->height = 3;
  p->has_amplitude = 1;
  EXPECT_TRUE(shm::validateInput(d, 1, b.data(), b.size(), rules()));
  p->has_amplitude = 0;
  expectReject(shm::validateInput(d, 2, b.data(), b.size(), rules()), Reject::Size, "for 4x3 depth");
  EXPECT_TRUE(shm::validateInput(d, 3, b.data(), b.size() - 12 * sizeof(float), rules()));
  p->width = 5;
  expectReject(shm::validateInput(d, 4, b.data(), b.size(), rules()), Reject::Size, "depth/tof frame 4: 5x3 pixels, expected 4x3");
  p->width = 4;
  p->has_amplitude = 9;
  expectReject(shm::validateInput(d, 5, b.data(), b.size(), rules()), Reject::Size, "has_amplitude 9");
}

TEST(ShmValidate, OutputKindIsNotAnInput) {
  const auto d = desc("pose", POLYLOC_KIND_POSE, 0);
  polyloc_pose p{};
  expectReject(shm::validateInput(d, 1, reinterpret_cast<const uint8_t*>(&p), sizeof p, rules()), Reject::Size,
               "pose frame 1: kind 10 is not an input kind");
}

TEST(ShmValidate, Commands) {
  const polyloc_channel_desc d = desc("cmd_vel", POLYLOC_KIND_COMMAND, 0);
  polyloc_command c{};
  c.stamp_ns = kNow;
  c.vx = 0.4, c.wz = -0.2;
  c.nav_state = POLYLOC_NAV_DRIVING;
  std::snprintf(c.status, sizeof c.status, "%s", "lab 1: passing the door");
  auto check = [&](const polyloc_command& m, size_t bytes = sizeof(polyloc_command)) {
    return shm::validateInput(d, 3, reinterpret_cast<const uint8_t*>(&m), bytes, rules());
  };
  EXPECT_TRUE(check(c)) << check(c).why;
  expectReject(check(c, 96), Reject::Size, "cmd_vel frame 3: 96 bytes, expected 104 for a command");
  polyloc_command bad = c;
  bad.vx = std::nan("");
  expectReject(check(bad), Reject::NaN, "vx is nan");
  bad = c;
  bad.wz = 1e19;  // finite, but no base turns at that
  expectReject(check(bad), Reject::NaN, "wz is 10000000000000000000");
  bad = c;
  bad.nav_state = 7;
  expectReject(check(bad), Reject::NaN, "nav_state 7, expected 0..3");
  bad = c;
  std::memset(bad.status, 'x', sizeof bad.status);
  expectReject(check(bad), Reject::Size, "status is not NUL-terminated");
  bad = c;
  bad.stamp_ns = kNow - 2'000'000'000;
  expectReject(check(bad), Reject::Stale, "ms old");
}

}  // namespace
}  // namespace polyloc
