// What real recordings bring that simulated ones did not: scanner geometry that is not centred
// (a CARMEN FLASER spans -90..+89 deg), a field of view written in radians, odometry only in
// the scans' fields, stamps that do not increase, and the restamping that makes such a log
// usable; plus the in-memory recording the real-log evaluation feeds its runs through.
#include <polyloc/io/memory_recording.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/restamp.hpp>
#include <polyloc/io/stamp_check.hpp>
#include <polyloc/io/recorded_geometry.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace polyloc::t_recorded_data {  // the file's own: the suite is compiled in batches (unity build)
namespace {

msg::LaserScan flaserLike(size_t n = 180) {
  msg::LaserScan s;
  s.angle_min = float(deg2rad(-90.0));
  s.angle_increment = float(deg2rad(1.0));
  s.range_max = 81.91f;
  s.ranges.assign(n, 2.0f);
  return s;
}

std::vector<RecordedMessage> readAll(RecordingReader& r) {
  std::vector<RecordedMessage> out;
  RecordedMessage m;
  while (r.next(m)) out.push_back(m);
  return out;
}

TEST(RecordedGeometry, SpecFromAnUncentredScanHasItsBeams) {
  const PlanarScannerSpec p = planarSpecFromScan(flaserLike(), 5.0);
  ASSERT_EQ(p.numBeams(), 180u);
  EXPECT_NEAR(rad2deg(p.angleMin()), -90.0, 1e-4);
  const BeamSet b = p.beams();
  // The last beam at +89 deg, not +89.5 (a centred 179 deg sensor) nor +90.
  EXPECT_NEAR(rad2deg(std::atan2(b.dy.back(), b.dx.back())), 89.0, 1e-4);
  EXPECT_NEAR(rad2deg(std::atan2(b.dy[90], b.dx[90])), 0.0, 1e-4);
  EXPECT_FLOAT_EQ(b.range_max, 81.91f);
  EXPECT_DOUBLE_EQ(p.rate_hz, 5.0);
}

TEST(RecordedGeometry, MismatchNamesBothGeometries) {
  PlanarScannerSpec centred;
  centred.fov_rad = deg2rad(179.0);
  centred.resolution_rad = deg2rad(1.0);
  const Sensor s{"laser", centred, Pose()};
  const std::string why = geometryMismatch(s, flaserLike());
  EXPECT_NE(why.find("-90.00..89.00 deg"), std::string::npos) << why;
  EXPECT_NE(why.find("sensor 'laser' has 180 beams, -89.50..89.50 deg"), std::string::npos) << why;
  const Sensor same{"laser", planarSpecFromScan(flaserLike()), Pose()};
  EXPECT_EQ(geometryMismatch(same, flaserLike()), "");
  EXPECT_NE(geometryMismatch(same, flaserLike(181)), "");  // a count that differs
}

TEST(RecordedGeometry, UnusableGeometryIsRefused) {
  msg::LaserScan s = flaserLike();
  s.angle_increment = 0;
  EXPECT_THROW(planarSpecFromScan(s), std::invalid_argument);
  s = flaserLike();
  s.range_max = 0;
  EXPECT_THROW(planarSpecFromScan(s), std::invalid_argument);
  EXPECT_THROW(planarSpecFromScan(flaserLike(1)), std::invalid_argument);
}

TEST(StampCheck, CountsZeroEqualAndBackwardsWithTheFirstPlace) {
  StampCheck c;
  const int64_t s = 1'000'000'000;
  c.add("/odom", 1 * s, 0);
  c.add("/odom", 2 * s, 1);
  c.add("/odom", 0, 2);      // zero: the first bad one
  c.add("/odom", 2 * s, 3);  // equal to the previous non-zero
  c.add("/odom", s, 4);      // backwards
  c.add("/scan", 5 * s, 5);
  const auto& t = c.topics().at("/odom");
  EXPECT_EQ(t.zero, 1u);
  EXPECT_EQ(t.equal, 1u);
  EXPECT_EQ(t.backwards, 1u);
  EXPECT_EQ(t.first_index, 2u);
  EXPECT_EQ(c.bad(), 3u);
  const auto w = c.warnings();
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("/odom: 3 of 5 stamps do not increase (1 zero, 1 equal to the previous, 1 backwards); the first is message 2: 0.000000 s after 2.000000 s"),
            std::string::npos) << w[0];
}

TEST(Restamp, StampsFollowTheOrderInLogTimeAndHeaders) {
  auto msgs = std::make_shared<std::vector<RecordedMessage>>();
  msg::Odometry o;
  o.header.stamp = msg::fromNs(0);
  msgs->push_back({"/odom", 0, 0, o});
  msg::LaserScan s = flaserLike();
  s.header.stamp = msg::fromNs(0);
  msgs->push_back({"/front_laser", 0, 0, s});
  msgs->push_back({"/odom", 0, 0, o});
  auto r = restampByOrder(readMemory(msgs), 4.0);
  const auto out = readAll(*r);
  ASSERT_EQ(out.size(), 3u);
  for (size_t i = 0; i < out.size(); ++i) {
    const int64_t want = kRestampStartNs + int64_t(i) * 250'000'000;
    EXPECT_EQ(out[i].log_time_ns, want);
    std::visit([&](const auto& m) {
      if constexpr (requires { m.header; }) {
        EXPECT_EQ(msg::toNs(m.header.stamp), want);
      }
    }, out[i].message);
  }
  const auto topics = restampByOrder(readMemory(msgs), 4.0)->topics();
  EXPECT_EQ(topics.size(), 2u);
  EXPECT_THROW(restampByOrder(readMemory(msgs), 0.0), std::invalid_argument);
  EXPECT_THROW(restampByOrder(readMemory(msgs), NAN), std::invalid_argument);
}

TEST(MemoryRecording, TopicsCountWhatItHolds) {
  auto msgs = std::make_shared<std::vector<RecordedMessage>>();
  msgs->push_back({"/odom", 10, 10, msg::Odometry{}});
  msgs->push_back({"/front_laser", 20, 20, flaserLike()});
  msgs->push_back({"/odom", 30, 30, msg::Odometry{}});
  auto r = readMemory(msgs);
  const auto t = r->topics();
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].name, "/odom");
  EXPECT_EQ(t[0].count, 2u);
  EXPECT_EQ(t[0].first_ns, 10);
  EXPECT_EQ(t[0].last_ns, 30);
  EXPECT_EQ(t[1].type, "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(readAll(*r).size(), 3u);
  EXPECT_EQ(readAll(*readMemory(msgs)).size(), 3u);  // a second reader reads it all again
}

// A FLASER line: n ranges, laser pose, odometry pose, stamp.
std::string flaser(int n, double x, double y, double th, double ox, double oy, double oth, double t) {
  std::string s = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) s += " 2.0";
  char tail[200];
  std::snprintf(tail, sizeof tail, " %g %g %g %g %g %g %.3f host %.3f\n", x, y, th, ox, oy, oth, t, t);
  return s + tail;
}

TEST(CarmenRecorded, FieldOfViewInRadiansIsTakenAsRadians) {
  test::TempDir dir;
  const std::string log = dir.write("csail.log", "PARAM laser_front_laser_fov 3.14159 1.0 host 1.0\n"
                                                 "PARAM laser_front_laser_resolution 0.5 1.0 host 1.0\n" +
                                                     flaser(361, 0, 0, 0, 0, 0, 0, 2.0));
  auto r = openRecording(log);
  const auto msgs = readAll(*r);
  ASSERT_EQ(msgs.size(), 3u);  // the odometry of the scan's fields (no ODOM lines), the scan, its pose
  const auto* s = std::get_if<msg::LaserScan>(&msgs.at(1).message);
  ASSERT_NE(s, nullptr);
  EXPECT_NEAR(rad2deg(s->angle_min), -90.0, 1e-3);
  EXPECT_NEAR(rad2deg(s->angle_increment), 0.5, 1e-4);
  ASSERT_EQ(r->stats().notes.size(), 2u);
  EXPECT_NE(r->stats().notes[0].find("csail.log:1: laser_front_laser_fov 3.14159: taken as radians (180 deg)"), std::string::npos)
      << r->stats().notes[0];
  EXPECT_EQ(r->stats().rejected, 0u);
}

TEST(CarmenRecorded, WithoutOdomLinesTheScansOdometryFieldsAreTheOdometry) {
  test::TempDir dir;
  const std::string raw = dir.write("raw.log", flaser(3, 5, 5, 0.1, 1.0, 2.0, 0.3, 10.0) + flaser(3, 6, 5, 0.1, 1.5, 2.0, 0.3, 11.0));
  auto r = openRecording(raw);
  const auto msgs = readAll(*r);
  ASSERT_EQ(msgs.size(), 6u);  // per scan: odometry, scan, laser pose
  const auto* o = std::get_if<msg::Odometry>(&msgs[3].message);
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(msgs[3].topic, "/odom");
  EXPECT_DOUBLE_EQ(o->pose.pose.position.x, 1.5);
  EXPECT_NEAR(2 * std::atan2(o->pose.pose.orientation.z, o->pose.pose.orientation.w), 0.3, 1e-12);
  EXPECT_EQ(msg::toNs(o->header.stamp), 11'000'000'000);
  EXPECT_EQ(msgs[4].topic, "/front_laser");  // after its odometry
  ASSERT_EQ(r->stats().notes.size(), 1u);
  EXPECT_NE(r->stats().notes[0].find("no ODOM lines"), std::string::npos);
  // With ODOM lines the scans' fields are not odometry.
  const std::string with = dir.write("odom.log", "ODOM 1 2 0.3 0 0 0 9.0 host 9.0\n" + flaser(3, 5, 5, 0.1, 1, 2, 0.3, 10.0));
  size_t odom = 0;
  for (const auto& m : readAll(*openRecording(with))) odom += m.topic == "/odom";
  EXPECT_EQ(odom, 1u);
}

}  // namespace
}  // namespace polyloc
