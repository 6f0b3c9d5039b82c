// CDR codec: round trips of every type, byte layouts checked by hand (alignment counted from
// after the 4-byte encapsulation header, as rmw_fastrtps does), and corrupt input that must give
// IoError, never a crash or a huge allocation. Also the ros2msg schema texts' layout.
#include "io_samples.hpp"

#include <polyloc/io/cdr.hpp>

#include <gtest/gtest.h>

#include <random>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_cdr {

using namespace polyloc;
using polyloc::test::sampleMessages;
using polyloc::test::sameMessage;

TEST(Cdr, RoundTripEveryType) {
  auto samples = sampleMessages(3);
  ASSERT_EQ(samples.size(), msg::supportedTypes().size());
  for (const auto& m : samples) {
    SCOPED_TRACE(msg::typeName(m));
    auto bytes = msg::encodeCdr(m);
    ASSERT_GE(bytes.size(), 4u);
    EXPECT_EQ(bytes[0], 0x00);  // encapsulation: CDR little endian, no options
    EXPECT_EQ(bytes[1], 0x01);
    EXPECT_EQ(bytes[2], 0x00);
    EXPECT_EQ(bytes[3], 0x00);
    msg::Message back = msg::decodeCdr(msg::typeName(m), bytes);
    EXPECT_TRUE(sameMessage(m, back));
  }
  // A few fields by value, so a symmetric mistake in encode and decode cannot hide.
  auto back = std::get<msg::LaserScan>(msg::decodeCdr("sensor_msgs/msg/LaserScan", msg::encodeCdr(samples[0])));
  EXPECT_EQ(back.header.frame_id, "laser_front");
  EXPECT_EQ(back.header.stamp.sec, 1700000003);
  ASSERT_EQ(back.ranges.size(), 5u);
  EXPECT_FLOAT_EQ(back.ranges[0], 4.25f);
  EXPECT_TRUE(std::isinf(back.ranges[2]));
  EXPECT_EQ(back.intensities.size(), 3u);
  auto odom = std::get<msg::Odometry>(msg::decodeCdr("nav_msgs/msg/Odometry", msg::encodeCdr(samples[4])));
  EXPECT_EQ(odom.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(odom.pose.covariance[35], 0.035);
  EXPECT_DOUBLE_EQ(odom.twist.covariance[1], -0.5);
  auto ci = std::get<msg::CameraInfo>(msg::decodeCdr("sensor_msgs/msg/CameraInfo", msg::encodeCdr(samples[3])));
  EXPECT_EQ(ci.d.size(), 5u);
  EXPECT_DOUBLE_EQ(ci.p[6], 25.0);
  EXPECT_TRUE(ci.roi.do_rectify);
  EXPECT_EQ(ci.binning_y, 2u);
  auto tr = std::get<msg::TrackArray>(msg::decodeCdr("polyloc_msgs/msg/TrackArray", msg::encodeCdr(samples[7])));
  ASSERT_EQ(tr.tracks.size(), 2u);
  EXPECT_EQ(tr.tracks[0].id, 7u);
  EXPECT_EQ(tr.tracks[0].status, 1);
  EXPECT_DOUBLE_EQ(tr.tracks[0].x, 5.5);
  EXPECT_DOUBLE_EQ(tr.tracks[1].covariance[3], 0.25);
  EXPECT_NE(msg::ros2msgSchema("polyloc_msgs/msg/TrackArray").find("MSG: polyloc_msgs/Track\nuint32 id"), std::string::npos);
}

template <size_t... I>
std::vector<msg::Message> defaultOfEachType(std::index_sequence<I...>) {
  return {msg::Message(std::in_place_index<I>)...};
}

TEST(Cdr, EmptyMessagesRoundTrip) {
  for (const msg::Message& m : defaultOfEachType(std::make_index_sequence<std::variant_size_v<msg::Message>>()))
    EXPECT_TRUE(sameMessage(m, msg::decodeCdr(msg::typeName(m), msg::encodeCdr(m)))) << msg::typeName(m);
}

TEST(Cdr, PoseStampedBytesByHand) {
  msg::PoseStamped p{{{1, 500}, "base"}, {{1.0, -2.0, 0.5}, {0, 0, 0, 1}}};
  const std::vector<uint8_t> expected = {
      0x00, 0x01, 0x00, 0x00,                          // encapsulation CDR_LE; offsets below from here
      0x01, 0x00, 0x00, 0x00,                          //  0 header.stamp.sec = 1
      0xf4, 0x01, 0x00, 0x00,                          //  4 header.stamp.nanosec = 500
      0x05, 0x00, 0x00, 0x00,                          //  8 frame_id length 5 (with the NUL)
      'b', 'a', 's', 'e', 0x00,                        // 12 "base\0"
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,        // 17 padding: float64 aligns to 8 -> 24
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f,  // 24 position.x = 1.0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xc0,  // 32 position.y = -2.0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe0, 0x3f,  // 40 position.z = 0.5
      0, 0, 0, 0, 0, 0, 0, 0,                          // 48 orientation.x = 0
      0, 0, 0, 0, 0, 0, 0, 0,                          // 56 orientation.y = 0
      0, 0, 0, 0, 0, 0, 0, 0,                          // 64 orientation.z = 0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f,  // 72 orientation.w = 1.0
  };
  EXPECT_EQ(msg::encodeCdr(p), expected);
  auto back = std::get<msg::PoseStamped>(msg::decodeCdr("geometry_msgs/msg/PoseStamped", expected));
  EXPECT_EQ(back.header.frame_id, "base");
  EXPECT_EQ(back.header.stamp.nanosec, 500u);
  EXPECT_EQ(back.pose.position.y, -2.0);
  EXPECT_EQ(back.pose.orientation.w, 1.0);
}

TEST(Cdr, LaserScanBytesByHand) {
  msg::LaserScan s;
  s.header.stamp.sec = 10;
  s.header.frame_id = "laser";
  s.angle_min = -1.5f, s.angle_max = 1.5f, s.angle_increment = 0.5f;
  s.scan_time = 0.25f, s.range_min = 0.125f, s.range_max = 8.0f;
  s.ranges = {1.0f, 2.0f};
  const std::vector<uint8_t> expected = {
      0x00, 0x01, 0x00, 0x00,  // encapsulation CDR_LE; offsets below from here
      0x0a, 0x00, 0x00, 0x00,  //  0 header.stamp.sec = 10
      0x00, 0x00, 0x00, 0x00,  //  4 header.stamp.nanosec = 0
      0x06, 0x00, 0x00, 0x00,  //  8 frame_id length 6 (with the NUL)
      'l', 'a', 's', 'e', 'r', 0x00,  // 12 "laser\0"
      0x00, 0x00,              // 18 padding: float32 aligns to 4 -> 20
      0x00, 0x00, 0xc0, 0xbf,  // 20 angle_min = -1.5
      0x00, 0x00, 0xc0, 0x3f,  // 24 angle_max = 1.5
      0x00, 0x00, 0x00, 0x3f,  // 28 angle_increment = 0.5
      0x00, 0x00, 0x00, 0x00,  // 32 time_increment = 0
      0x00, 0x00, 0x80, 0x3e,  // 36 scan_time = 0.25
      0x00, 0x00, 0x00, 0x3e,  // 40 range_min = 0.125
      0x00, 0x00, 0x00, 0x41,  // 44 range_max = 8
      0x02, 0x00, 0x00, 0x00,  // 48 ranges: count 2
      0x00, 0x00, 0x80, 0x3f,  // 52 ranges[0] = 1
      0x00, 0x00, 0x00, 0x40,  // 56 ranges[1] = 2
      0x00, 0x00, 0x00, 0x00,  // 60 intensities: count 0, no elements
  };
  EXPECT_EQ(msg::encodeCdr(s), expected);
  auto back = std::get<msg::LaserScan>(msg::decodeCdr("sensor_msgs/msg/LaserScan", expected));
  EXPECT_EQ(back.ranges, (std::vector<float>{1.0f, 2.0f}));
  EXPECT_EQ(back.range_max, 8.0f);
}

TEST(Cdr, BoolIsOneByteAndSequencesOfDoublesAlign) {
  // CameraInfo: "plumb_bob" ends at an odd offset; d (float64[]) count aligns to 4, its first
  // element to 8; roi.do_rectify is one byte at the very end.
  msg::CameraInfo ci;
  ci.d = {0.5};
  ci.roi.do_rectify = true;
  auto b = msg::encodeCdr(ci);
  // header: sec 0, nanosec 4, frame_id len 8 + "\0" 12 -> 13; height @16, width @20,
  // distortion_model len @24, "plumb_bob\0" @28..37, pad to 40, d count @40, pad to 48,
  // d[0] @48, k @56 (72 bytes), r @128, p @200 (96 bytes), binning @296/@300, roi @304..319, bool @320
  ASSERT_EQ(b.size(), 4u + 321u);
  EXPECT_EQ(b[4 + 40], 1);                                     // d count
  EXPECT_EQ(b[4 + 48 + 7], 0x3f);                              // d[0] = 0.5 -> 00..e0 3f
  EXPECT_EQ(b[4 + 48 + 6], 0xe0);
  EXPECT_EQ(b[4 + 320], 1);                                    // do_rectify
}

TEST(Cdr, TruncatedBuffersThrow) {
  for (const auto& m : sampleMessages()) {
    auto bytes = msg::encodeCdr(m);
    for (size_t n = 0; n < bytes.size(); ++n) {
      SCOPED_TRACE(std::string(msg::typeName(m)) + " cut to " + std::to_string(n));
      try {
        msg::decodeCdr(msg::typeName(m), std::span(bytes.data(), n));
        ADD_FAILURE() << "decoded a truncated message";
      } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(msg::typeName(m)), std::string::npos) << e.what();
      }
    }
  }
}

TEST(Cdr, BitFlipsGiveIoErrorOrAMessage) {
  std::mt19937 rng(7);
  for (const auto& m : sampleMessages()) {
    const auto good = msg::encodeCdr(m);
    for (int trial = 0; trial < 2000; ++trial) {
      auto bytes = good;
      int flips = 1 + trial % 3;
      for (int f = 0; f < flips; ++f) bytes[rng() % bytes.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
      try {
        msg::decodeCdr(msg::typeName(m), bytes);
      } catch (const IoError&) {
      }  // anything else escapes and fails the test
    }
  }
}

TEST(Cdr, AbsurdSequenceLengthIsRejectedBeforeAllocating) {
  msg::LaserScan s;
  s.header.frame_id = "laser";
  s.ranges = {1.0f, 2.0f};  // count at payload offset 48, as in LaserScanBytesByHand
  auto bytes = msg::encodeCdr(s);
  bytes[4 + 48] = 0xf0, bytes[4 + 49] = 0xff, bytes[4 + 50] = 0xff, bytes[4 + 51] = 0xff;  // ranges count
  try {
    msg::decodeCdr("sensor_msgs/msg/LaserScan", bytes);
    FAIL() << "no error";
  } catch (const IoError& e) {
    std::string w = e.what();
    EXPECT_NE(w.find("ranges"), std::string::npos) << w;
    EXPECT_NE(w.find("LaserScan"), std::string::npos) << w;
  }
  msg::TFMessage tf;
  tf.transforms.resize(1);
  auto t = msg::encodeCdr(tf);
  t[4] = 0xff, t[5] = 0xff, t[6] = 0xff, t[7] = 0x7f;
  EXPECT_THROW(msg::decodeCdr("tf2_msgs/msg/TFMessage", t), IoError);
}

TEST(Cdr, UnknownTypeAndBadEncapsulation) {
  std::vector<uint8_t> b = {0x00, 0x01, 0x00, 0x00, 1, 2, 3, 4};
  try {
    msg::decodeCdr("std_msgs/msg/String", b);
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("std_msgs/msg/String"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("unknown"), std::string::npos);
  }
  b[1] = 0x03;  // PL_CDR_LE: not what ROS 2 messages use
  EXPECT_THROW(msg::decodeCdr("geometry_msgs/msg/PoseStamped", b), IoError);
  EXPECT_THROW(msg::decodeCdr("geometry_msgs/msg/PoseStamped", {}), IoError);
}

TEST(Cdr, BigEndianInputDecodes) {
  // Written by a big-endian peer: 00 00 encapsulation, fields big endian.
  std::vector<uint8_t> b = {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x07,  // sec 7
                            0x00, 0x00, 0x00, 0x09, 0x00, 0x00, 0x00, 0x01, 0x00,  // nanosec 9, ""
                            0, 0, 0};  // padding from 13 to 16
  b.resize(4 + 16 + 56, 0);
  b[4 + 16] = 0x3f, b[4 + 17] = 0xf0;  // position.x = 1.0 big endian
  auto p = std::get<msg::PoseStamped>(msg::decodeCdr("geometry_msgs/msg/PoseStamped", b));
  EXPECT_EQ(p.header.stamp.sec, 7);
  EXPECT_EQ(p.header.stamp.nanosec, 9u);
  EXPECT_EQ(p.pose.position.x, 1.0);
}

TEST(Cdr, SchemaTextsCarryEveryDependencyOnce) {
  const std::string sep = "\n================================================================================\nMSG: ";
  const std::string& scan = msg::ros2msgSchema("sensor_msgs/msg/LaserScan");
  EXPECT_EQ(scan.rfind("std_msgs/Header header\nfloat32 angle_min\n", 0), 0u) << scan;
  EXPECT_NE(scan.find(sep + "std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id"), std::string::npos);
  EXPECT_NE(scan.find(sep + "builtin_interfaces/Time\nint32 sec\nuint32 nanosec"), std::string::npos);

  const std::string& odom = msg::ros2msgSchema("nav_msgs/msg/Odometry");
  for (const char* dep : {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseWithCovariance",
                          "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion",
                          "geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist", "geometry_msgs/Vector3"}) {
    std::string marker = sep + dep + "\n";
    size_t at = odom.find(marker);
    EXPECT_NE(at, std::string::npos) << dep;
    EXPECT_EQ(odom.find(marker, at + 1), std::string::npos) << dep << " twice";
  }
  EXPECT_NE(msg::ros2msgSchema("sensor_msgs/msg/PointCloud2").find("uint8 FLOAT64 = 8"), std::string::npos);
  EXPECT_NE(msg::ros2msgSchema("sensor_msgs/msg/CameraInfo").find("float64[12] p"), std::string::npos);
  for (const auto& t : msg::supportedTypes()) EXPECT_FALSE(msg::ros2msgSchema(t).empty()) << t;
  EXPECT_THROW(msg::ros2msgSchema("std_msgs/msg/String"), IoError);
}

}  // namespace polyloc::t_cdr
