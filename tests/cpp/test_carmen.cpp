// CARMEN logs: every supported message checked field by field (with the laser pose that follows
// each scan), the same log gzipped, malformed lines counted with file:line, and truncated or
// bit-flipped logs (plain and gzip) that must never crash the reader.
#include <polyloc/geometry/pose.hpp>
#include <polyloc/io/recording.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <random>

namespace polyloc::t_carmen {  // the file's own: the suite is compiled in batches (unity build)
namespace {

const char* kLog =
    "# CARMEN log written by hand for polyloc's tests\n"
    "PARAM robot_front_laser_max 50.0 1000.0 host 0.0\n"
    "PARAM laser_front_laser_resolution 0.5 1000.0 host 0.0\n"
    "ODOM 1.5 -2.0 0.5 0.3 0.1 0.0 1000.250000 host 0.25\n"
    "FLASER 3 1.0 2.0 3.5 1.5 -2.0 0.5 1.4 -2.1 0.4 1000.5 host 0.5\n"
    "RLASER 2 4.0 5.0 1.5 -2.0 0.5 1.5 -2.0 0.5 1000.6 host 0.6\n"
    "SYNC 1000.65 host 0.65\n"
    "TRUEPOS 1 2 3 1 2 3 1000.7 host 0.7\n"
    "TRUEPOS 1 2 3 1 2 3 1000.8 host 0.8\n"
    // robot at (1, 2) facing +y, laser 0.1 m ahead of it
    "ROBOTLASER1 0 -1.5 3.0 1.5 30.0 0.01 0 3 1.0 2.0 nan 3 10 20 30 "
    "1.0 2.1 1.5707963267948966 1.0 2.0 1.5707963267948966 0.2 0.05 0.5 0.3 0.0 1001.0 host 1.0\n"
    "ROBOTLASER1 0 -1.5 3.0 1.5 30.0 0.01 0 2 1.0 2.0 0 "
    "1.0 2.1 1.5707963267948966 1.0 2.0 1.5707963267948966 0.2 0.05 0.5 0.3 0.0 1001.1 host 1.1\n"
    // the laser now 0.2 m ahead and turned by 0.1 rad
    "ROBOTLASER1 0 -1.5 3.0 1.5 30.0 0.01 0 1 7.0 0 "
    "0.0 0.2 0.1 0.0 0.0 0.0 0.2 0.05 0.5 0.3 0.0 1001.2 host 1.2\n";

std::vector<RecordedMessage> readAll(RecordingReader& r) {
  std::vector<RecordedMessage> out;
  RecordedMessage m;
  while (r.next(m)) out.push_back(m);
  return out;
}

void writeGz(const std::string& path, const std::string& content) {
  gzFile f = gzopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, content.data(), static_cast<unsigned>(content.size())), int(content.size()));
  gzclose(f);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// A laser pose message: topic, stamp, frame "world", position and yaw.
void expectPose(const RecordedMessage& m, const std::string& topic, int64_t ns, double x, double y, double yaw) {
  EXPECT_EQ(m.topic, topic);
  EXPECT_EQ(m.log_time_ns, ns);
  EXPECT_EQ(m.publish_time_ns, ns);
  ASSERT_TRUE(std::holds_alternative<msg::PoseStamped>(m.message)) << msg::typeName(m.message);
  const auto& p = std::get<msg::PoseStamped>(m.message);
  EXPECT_EQ(p.header.frame_id, "world");
  EXPECT_EQ(msg::toNs(p.header.stamp), ns);
  EXPECT_DOUBLE_EQ(p.pose.position.x, x);
  EXPECT_DOUBLE_EQ(p.pose.position.y, y);
  EXPECT_DOUBLE_EQ(p.pose.position.z, 0.0);
  EXPECT_NEAR(p.pose.orientation.x, 0.0, 1e-15);
  EXPECT_NEAR(p.pose.orientation.y, 0.0, 1e-15);
  EXPECT_NEAR(p.pose.orientation.z, std::sin(yaw / 2), 1e-12);
  EXPECT_NEAR(p.pose.orientation.w, std::cos(yaw / 2), 1e-12);
}

void checkHandWrittenLog(const std::vector<RecordedMessage>& m) {
  ASSERT_EQ(m.size(), 13u);
  // ODOM
  EXPECT_EQ(m[0].topic, "/odom");
  EXPECT_EQ(m[0].log_time_ns, 1000250000000);
  EXPECT_EQ(m[0].publish_time_ns, 1000250000000);
  const auto& o = std::get<msg::Odometry>(m[0].message);
  EXPECT_EQ(o.header.frame_id, "odom");
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_EQ(msg::toNs(o.header.stamp), 1000250000000);
  EXPECT_DOUBLE_EQ(o.pose.pose.position.x, 1.5);
  EXPECT_DOUBLE_EQ(o.pose.pose.position.y, -2.0);
  EXPECT_NEAR(o.pose.pose.orientation.z, std::sin(0.25), 1e-12);
  EXPECT_NEAR(o.pose.pose.orientation.w, std::cos(0.25), 1e-12);
  EXPECT_DOUBLE_EQ(o.twist.twist.linear.x, 0.3);
  EXPECT_DOUBLE_EQ(o.twist.twist.angular.z, 0.1);
  // FLASER with the PARAM resolution and max range
  EXPECT_EQ(m[1].topic, "/front_laser");
  EXPECT_EQ(m[1].log_time_ns, 1000500000000);
  const auto& f = std::get<msg::LaserScan>(m[1].message);
  EXPECT_EQ(f.header.frame_id, "front_laser");
  EXPECT_EQ(f.ranges, (std::vector<float>{1.0f, 2.0f, 3.5f}));
  EXPECT_TRUE(f.intensities.empty());
  EXPECT_FLOAT_EQ(f.angle_min, float(-M_PI / 2));
  EXPECT_FLOAT_EQ(f.angle_increment, float(deg2rad(0.5)));
  EXPECT_FLOAT_EQ(f.angle_max, float(-M_PI / 2 + deg2rad(1.0)));
  EXPECT_FLOAT_EQ(f.range_max, 50.0f);
  // Right after it, the logged laser pose (x y theta), not the odometry pose after it.
  expectPose(m[2], "/front_laser_pose", 1000500000000, 1.5, -2.0, 0.5);
  // RLASER with the defaults: 1 deg, 80 m
  EXPECT_EQ(m[3].topic, "/rear_laser");
  const auto& r = std::get<msg::LaserScan>(m[3].message);
  EXPECT_EQ(r.header.frame_id, "rear_laser");
  EXPECT_EQ(r.ranges, (std::vector<float>{4.0f, 5.0f}));
  EXPECT_FLOAT_EQ(r.angle_increment, float(deg2rad(1.0)));
  EXPECT_FLOAT_EQ(r.range_max, 80.0f);
  expectPose(m[4], "/rear_laser_pose", 1000600000000, 1.5, -2.0, 0.5);
  // ROBOTLASER1: the mount first, then the scan, then its laser pose
  EXPECT_EQ(m[5].topic, "/tf");
  EXPECT_EQ(m[5].log_time_ns, 1001000000000);
  const auto& tf = std::get<msg::TFMessage>(m[5].message);
  ASSERT_EQ(tf.transforms.size(), 1u);
  EXPECT_EQ(tf.transforms[0].header.frame_id, "base_link");
  EXPECT_EQ(tf.transforms[0].child_frame_id, "laser");
  EXPECT_NEAR(tf.transforms[0].transform.translation.x, 0.1, 1e-9);
  EXPECT_NEAR(tf.transforms[0].transform.translation.y, 0.0, 1e-9);
  EXPECT_NEAR(tf.transforms[0].transform.rotation.z, 0.0, 1e-9);
  EXPECT_EQ(m[6].topic, "/robot_laser");
  const auto& s = std::get<msg::LaserScan>(m[6].message);
  EXPECT_EQ(s.header.frame_id, "laser");
  EXPECT_EQ(msg::toNs(s.header.stamp), 1001000000000);
  ASSERT_EQ(s.ranges.size(), 3u);
  EXPECT_EQ(s.ranges[0], 1.0f);
  EXPECT_EQ(s.ranges[1], 2.0f);
  EXPECT_TRUE(std::isnan(s.ranges[2]));
  EXPECT_EQ(s.intensities, (std::vector<float>{10, 20, 30}));
  EXPECT_FLOAT_EQ(s.angle_min, -1.5f);
  EXPECT_FLOAT_EQ(s.angle_increment, 1.5f);
  EXPECT_FLOAT_EQ(s.angle_max, 1.5f);
  EXPECT_FLOAT_EQ(s.range_max, 30.0f);
  // laser_x laser_y laser_theta, not the robot pose
  expectPose(m[7], "/robot_laser_pose", 1001000000000, 1.0, 2.1, 1.5707963267948966);
  // Same mount: no new /tf. No remissions: no intensities.
  EXPECT_EQ(m[8].topic, "/robot_laser");
  EXPECT_EQ(m[8].log_time_ns, 1001100000000);
  EXPECT_TRUE(std::get<msg::LaserScan>(m[8].message).intensities.empty());
  expectPose(m[9], "/robot_laser_pose", 1001100000000, 1.0, 2.1, 1.5707963267948966);
  // New mount: /tf again.
  EXPECT_EQ(m[10].topic, "/tf");
  const auto& tf2 = std::get<msg::TFMessage>(m[10].message).transforms.at(0).transform;
  EXPECT_NEAR(tf2.translation.y, 0.2, 1e-9);
  EXPECT_NEAR(tf2.rotation.z, std::sin(0.05), 1e-9);
  EXPECT_EQ(m[11].topic, "/robot_laser");
  EXPECT_EQ(std::get<msg::LaserScan>(m[11].message).ranges, std::vector<float>{7.0f});
  expectPose(m[12], "/robot_laser_pose", 1001200000000, 0.0, 0.2, 0.1);
}

TEST(Carmen, HandWrittenLogFieldByField) {
  test::TempDir dir;
  auto r = openRecording(dir.write("hand.log", kLog));
  EXPECT_EQ(r->format(), "carmen");
  checkHandWrittenLog(readAll(*r));
  EXPECT_EQ(r->stats().messages, 13u);
  // TRUEPOS twice: one warning for the type.
  EXPECT_EQ(r->stats().rejected, 1u);
  ASSERT_EQ(r->stats().warnings.size(), 1u);
  EXPECT_NE(r->stats().warnings[0].find("hand.log:8: TRUEPOS"), std::string::npos) << r->stats().warnings[0];
}

TEST(Carmen, GzipGivesTheSameMessages) {
  test::TempDir dir;
  writeGz(dir.file("hand.clf.gz"), kLog);
  auto r = openRecording(dir.file("hand.clf.gz"));
  EXPECT_EQ(r->format(), "carmen");
  checkHandWrittenLog(readAll(*r));
  EXPECT_EQ(r->stats().rejected, 1u);
  // A gzip log with no telling extension is found by its content.
  writeGz(dir.file("noext"), kLog);
  checkHandWrittenLog(readAll(*openRecording(dir.file("noext"))));
}

TEST(Carmen, TopicsByStreamingPassDoNotDisturbNext) {
  test::TempDir dir;
  auto r = openCarmen(dir.write("hand.log", kLog));
  RecordedMessage first;
  ASSERT_TRUE(r->next(first));
  const auto topics = r->topics();
  ASSERT_EQ(topics.size(), 8u);
  EXPECT_EQ(topics[0].name, "/odom");
  EXPECT_EQ(topics[0].type, "nav_msgs/msg/Odometry");
  EXPECT_EQ(topics[2].name, "/front_laser_pose");
  EXPECT_EQ(topics[2].type, "geometry_msgs/msg/PoseStamped");
  EXPECT_EQ(topics[2].count, 1u);
  EXPECT_EQ(topics[6].name, "/robot_laser");
  EXPECT_EQ(topics[6].type, "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(topics[6].count, 3u);
  EXPECT_EQ(topics[6].first_ns, 1001000000000);
  EXPECT_EQ(topics[6].last_ns, 1001200000000);
  EXPECT_NEAR(topics[6].rateHz(), 10.0, 1e-9);
  EXPECT_EQ(topics[7].name, "/robot_laser_pose");
  EXPECT_EQ(topics[7].count, 3u);
  EXPECT_EQ(topics[5].name, "/tf");
  EXPECT_EQ(topics[5].count, 2u);
  auto rest = readAll(*r);
  EXPECT_EQ(rest.size(), 12u);
  EXPECT_EQ(rest[0].topic, "/front_laser");
  EXPECT_EQ(r->stats().messages, 13u);
}

TEST(Carmen, MalformedLinesAreCountedWithFileAndLine) {
  test::TempDir dir;
  const std::string path = dir.write("bad.log",
      "ODOM 1 2 3 0 0 0 5.0 host 5.0\n"                       // 1 ok
      "FLASER 180 1.0 2.0 0 0 0 0 0 0 5.0 host 5.0\n"         // 2 too few ranges
      "ODOM 1 2 abc 0 0 0 5.0 host 5.0\n"                     // 3 non-numeric
      "FLASER 99999999 1 2 3 4 5 6 7 8 9 10 11\n"             // 4 absurd count
      "ODOM 1 2 3\n"                                          // 5 too few fields
      "\x01\x02garbage \xff\n"                                // 6 binary
      "ODOM 1 2 3 0 0 0 notatime host 5.0\n"                  // 7 bad time
      "ROBOTLASER1 0 -1.5 3.0 1.5 30.0 0.01 0 2 1.0 0 0 0 0 0 0 0 0 0 0 0 0 6 h 6\n"  // 8 short
      "FLASER 2 1.0 x 0 0 0 0 0 0 5.0 host 5.0\n"             // 9 bad range
      "ODOM 4 5 6 0 0 0 6.0 host 6.0\n");                     // 10 ok
  auto r = openRecording(path);
  auto m = readAll(*r);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[1].log_time_ns, 6000000000);
  const auto& w = r->stats().warnings;
  EXPECT_EQ(r->stats().rejected, 8u);
  ASSERT_EQ(w.size(), 8u);
  EXPECT_EQ(w[0], path + ":2: FLASER: expected 180 ranges, got 2");
  const int lines[] = {2, 3, 4, 5, 6, 7, 8, 9};
  for (int k = 0; k < 8; ++k)
    EXPECT_EQ(w[k].rfind(path + ":" + std::to_string(lines[k]) + ": ", 0), 0u) << w[k];
  EXPECT_NE(w[1].find("'abc'"), std::string::npos) << w[1];
}

// Finite but absurd numbers (1e19 m) are refused like non-numbers; time going backwards is kept
// (a log's order is its order) and noted once.
TEST(Carmen, NumbersBeyondTheDomainAreRefusedAndBackwardsTimeIsNoted) {
  test::TempDir dir;
  const std::string path = dir.write("hostile.log",
      "ODOM 1e19 2 3 0 0 0 5.0 host 5.0\n"                  // 1 x beyond 1e6
      "ODOM 1 -1e300 3 0 0 0 5.0 host 5.0\n"                // 2 y beyond 1e6
      "FLASER 2 1.0 2.0 0 0 0 1e19 0 0 5.0 host 5.0\n"      // 3 odometry x beyond 1e6
      "ODOM 1 2 3 0 0 0 6.0 host 6.0\n"                     // 4 ok
      "ODOM -0 1e-300 0 0 0 0 5.5 host 5.5\n"               // 5 ok, earlier than line 4
      "ODOM 1 2 3 0 0 0 4.0 host 4.0\n");                   // 6 ok, earlier again (not noted twice)
  auto r = openRecording(path);
  auto m = readAll(*r);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(r->stats().rejected, 3u);
  ASSERT_EQ(r->stats().warnings.size(), 3u);
  EXPECT_NE(r->stats().warnings[0].find(":1: ODOM: field 1 is '1e19': beyond +-1e6"), std::string::npos) << r->stats().warnings[0];
  size_t backwards = 0;
  for (const auto& n : r->stats().notes) backwards += n.find("time goes backwards") != std::string::npos;
  EXPECT_EQ(backwards, 1u);
}

// A longer log of every type for the damage tests.
std::string longLog() {
  std::string s = "# long\nPARAM robot_front_laser_max 50.0 0 host 0\n";
  for (int i = 0; i < 60; ++i) {
    const std::string t = std::to_string(100 + i) + ".5 host 1.0\n";
    s += "ODOM 1.5 -2.0 0.5 0.3 0.1 0.0 " + t;
    s += "FLASER 4 1 2 3 4 0 0 0 0 0 0 " + t;
    s += "RLASER 2 1 2 0 0 0 0 0 0 " + t;
    s += "ROBOTLASER1 0 -1.5 3.0 1.0 30 0.01 0 4 1 2 3 4 4 5 6 7 8 " + std::to_string(i / 20) +
         " 0 0 0 0 0 0 0 0 0 0 " + t;
  }
  return s;
}

TEST(Carmen, TruncatedAndBitFlippedLogsNeverCrash) {
  test::TempDir dir;
  const std::string log = longLog();
  writeGz(dir.file("long.gz"), log);
  const std::string gz = slurp(dir.file("long.gz"));
  {
    auto r = openCarmen(dir.write("long.log", log));
    EXPECT_EQ(readAll(*r).size(), 60u * 7 + 3);  // 4 messages, 3 laser poses; one /tf per mount
    EXPECT_EQ(r->stats().rejected, 0u);
  }
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const bool use_gz = trial % 2;
    std::string bytes = use_gz ? gz : log;
    if (trial % 4 < 2) {
      bytes.resize(std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(rng));
    } else {
      const int flips = std::uniform_int_distribution<int>(1, 16)(rng);
      for (int k = 0; k < flips; ++k) {
        const size_t at = std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(rng);
        bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8)));
      }
    }
    const std::string path = dir.write(use_gz ? "damaged.gz" : "damaged.log", bytes);
    std::unique_ptr<RecordingReader> r;
    ASSERT_NO_THROW(r = openCarmen(path)) << "trial " << trial;
    std::vector<RecordedMessage> got;
    ASSERT_NO_THROW(got = readAll(*r)) << "trial " << trial;
    ASSERT_NO_THROW(r->topics()) << "trial " << trial;
    EXPECT_LE(got.size(), 60u * 7 + 3 + 40);
    for (const auto& w : r->stats().warnings) EXPECT_EQ(w.rfind(path + ":", 0), 0u) << w;
  }
  // A truncated gzip says so.
  auto r = openCarmen(dir.write("cut.gz", gz.substr(0, gz.size() / 2)));
  readAll(*r);
  ASSERT_FALSE(r->stats().warnings.empty());
  EXPECT_NE(r->stats().warnings.back().find("gzip data corrupt or truncated"), std::string::npos)
      << r->stats().warnings.back();
}

TEST(Carmen, OpenRecordingDispatchAndErrors) {
  test::TempDir dir;
  EXPECT_EQ(openRecording(dir.write("plain", kLog))->format(), "carmen");  // by first line
  try {
    openRecording(dir.file("missing.log"));
    FAIL();
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("missing.log") + ": does not exist");
  }
  try {
    openRecording(dir.write("notes.md", "# title\nsome prose\n"));
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("notes.md: not a recording polyloc can read"), std::string::npos);
  }
  EXPECT_THROW(openCarmen(dir.file("missing.log")), IoError);
}

}  // namespace
}  // namespace polyloc
