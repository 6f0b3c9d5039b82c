// ROS 2 bags (sqlite3 storage): our writer -> our reader for every message type; a bag built by
// hand with the sqlite3 API in rosbag2's (Jazzy) layout; corrupt, truncated and bit-flipped
// .db3 files; undecodable messages, unsupported types and missing split files.
#include <polyloc/io/cdr.hpp>
#include <polyloc/io/recording.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <random>

namespace polyloc::t_ros2bag {  // the file's own: the suite is compiled in batches (unity build)
namespace {

namespace fs = std::filesystem;

msg::Header header(int64_t ns, const char* frame) { return {msg::fromNs(ns), frame}; }

// One message of every type, each field set to something that is not its default.
std::vector<std::pair<std::string, msg::Message>> everyType(int64_t ns) {
  msg::LaserScan scan;
  scan.header = header(ns, "front_laser");
  scan.angle_min = -2.35f, scan.angle_max = 2.35f, scan.angle_increment = 0.01f;
  scan.time_increment = 1e-5f, scan.scan_time = 0.08f, scan.range_min = 0.05f, scan.range_max = 30.f;
  scan.ranges = {1.5f, 2.25f, 30.f, 0.f};
  scan.intensities = {100.f, 200.f, 0.f, 1.f};
  msg::PointCloud2 cloud;
  cloud.header = header(ns, "lidar");
  cloud.height = 1, cloud.width = 2, cloud.point_step = 12, cloud.row_step = 24, cloud.is_dense = false;
  cloud.fields = {{"x", 0, msg::PointField::FLOAT32, 1}, {"y", 4, msg::PointField::FLOAT32, 1},
                  {"z", 8, msg::PointField::FLOAT32, 1}};
  for (int i = 0; i < 24; ++i) cloud.data.push_back(static_cast<uint8_t>(i * 7));
  msg::Image image;
  image.header = header(ns, "tof");
  image.height = 2, image.width = 3, image.encoding = "32FC1", image.step = 12;
  image.data.assign(24, 0x3f);
  msg::CameraInfo info;
  info.header = header(ns, "tof");
  info.height = 2, info.width = 3, info.d = {0.1, -0.2, 0.0, 0.001, 0.0};
  info.k = {100, 0, 1.5, 0, 100, 1, 0, 0, 1};
  info.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.p = {100, 0, 1.5, 0, 0, 100, 1, 0, 0, 0, 1, 0};
  info.binning_x = 1, info.roi = {1, 2, 3, 4, true};
  msg::Odometry odom;
  odom.header = header(ns, "odom");
  odom.child_frame_id = "base_link";
  odom.pose.pose = {{1, 2, 0}, {0, 0, 0.6, 0.8}};
  odom.pose.covariance[0] = 0.01, odom.pose.covariance[35] = 0.02;
  odom.twist.twist = {{0.5, 0, 0}, {0, 0, 0.1}};
  odom.twist.covariance[7] = 0.03;
  msg::TFMessage tf;
  tf.transforms.push_back({header(ns, "base_link"), "front_laser", {{0.2, 0.1, 0.3}, {0, 0, 0.6, 0.8}}});
  tf.transforms.push_back({header(ns, "map"), "odom", {{-1, 4, 0}, {0, 0, 0, 1}}});
  msg::PoseStamped pose{header(ns, "map"), {{3, 4, 0.1}, {0, 0, 0.28, 0.96}}};
  return {{"/front_laser", scan}, {"/points", cloud}, {"/tof/depth", image}, {"/tof/camera_info", info},
          {"/odom", odom},        {"/tf", tf},        {"/ground_truth", pose}};
}

// Values equal: the fields that differ per type checked by name, and everything else through
// the bytes of its encoding (two messages with equal bytes have equal fields).
void expectSame(const msg::Message& a, const msg::Message& b) {
  ASSERT_EQ(a.index(), b.index());
  EXPECT_EQ(msg::encodeCdr(a), msg::encodeCdr(b)) << msg::typeName(a);
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        const T& y = std::get<T>(b);
        if constexpr (std::is_same_v<T, msg::LaserScan>) {
          EXPECT_EQ(x.ranges, y.ranges);
          EXPECT_EQ(x.intensities, y.intensities);
          EXPECT_EQ(x.angle_min, y.angle_min);
          EXPECT_EQ(x.header.frame_id, y.header.frame_id);
        } else if constexpr (std::is_same_v<T, msg::PointCloud2>) {
          EXPECT_EQ(x.data, y.data);
          ASSERT_EQ(x.fields.size(), y.fields.size());
          EXPECT_EQ(x.fields[2].name, y.fields[2].name);
          EXPECT_EQ(x.is_dense, y.is_dense);
        } else if constexpr (std::is_same_v<T, msg::Image>) {
          EXPECT_EQ(x.encoding, y.encoding);
          EXPECT_EQ(x.data, y.data);
        } else if constexpr (std::is_same_v<T, msg::CameraInfo>) {
          EXPECT_EQ(x.d, y.d);
          EXPECT_EQ(x.k, y.k);
          EXPECT_EQ(x.p, y.p);
          EXPECT_EQ(x.roi.do_rectify, y.roi.do_rectify);
        } else if constexpr (std::is_same_v<T, msg::Odometry>) {
          EXPECT_EQ(x.child_frame_id, y.child_frame_id);
          EXPECT_EQ(x.pose.covariance, y.pose.covariance);
          EXPECT_EQ(x.twist.twist.linear.x, y.twist.twist.linear.x);
        } else if constexpr (std::is_same_v<T, msg::TFMessage>) {
          ASSERT_EQ(x.transforms.size(), y.transforms.size());
          EXPECT_EQ(x.transforms[1].child_frame_id, y.transforms[1].child_frame_id);
          EXPECT_EQ(x.transforms[0].transform.translation.z, y.transforms[0].transform.translation.z);
        } else if constexpr (std::is_same_v<T, msg::PoseStamped>) {
          EXPECT_EQ(x.pose.position.z, y.pose.position.z);
          EXPECT_EQ(x.pose.orientation.w, y.pose.orientation.w);
        }
      },
      a);
}

std::vector<RecordedMessage> readAll(RecordingReader& r) {
  std::vector<RecordedMessage> out;
  RecordedMessage m;
  while (r.next(m)) out.push_back(m);
  return out;
}

// A bag of `rounds` x every type, 0.1 s apart, written out of time order within each round.
std::string writeBag(const test::TempDir& dir, const std::string& name, int rounds) {
  auto w = createRos2Bag(dir.file(name));
  for (int k = 0; k < rounds; ++k) {
    const int64_t ns = 1700000000000000000 + k * 100000000LL;
    auto msgs = everyType(ns);
    for (size_t i = msgs.size(); i-- > 0;) w->write(msgs[i].first, ns + int64_t(i), msgs[i].second);
  }
  w->close();
  return dir.file(name);
}

TEST(Ros2Bag, WriteReadRoundTripOfEveryType) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 3);
  EXPECT_TRUE(fs::exists(bag + "/metadata.yaml"));
  EXPECT_TRUE(fs::exists(bag + "/run_0.db3"));
  for (const std::string& path : {bag, bag + "/metadata.yaml", bag + "/run_0.db3"}) {
    auto r = openRecording(path);
    EXPECT_EQ(r->format(), "ros2bag");
    const auto got = readAll(*r);
    ASSERT_EQ(got.size(), 21u) << path;
    EXPECT_EQ(r->stats().rejected, 0u) << (r->stats().warnings.empty() ? "" : r->stats().warnings[0]);
    for (size_t j = 0; j < got.size(); ++j) {
      const int64_t ns = 1700000000000000000 + int64_t(j / 7) * 100000000LL;
      const auto expected = everyType(ns)[j % 7];  // time order: i ascending within a round
      EXPECT_EQ(got[j].topic, expected.first);
      EXPECT_EQ(got[j].log_time_ns, ns + int64_t(j % 7));
      EXPECT_EQ(got[j].publish_time_ns, got[j].log_time_ns);
      expectSame(got[j].message, expected.second);
    }
  }
}

TEST(Ros2Bag, TopicsCountsAndTimes) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 4);
  const int64_t t0 = 1700000000000000000, t1 = t0 + 300000000 + 6;
  // From metadata.yaml: counts per topic, the bag's span for every topic.
  auto from_meta = openRos2Bag(bag)->topics();
  ASSERT_EQ(from_meta.size(), 7u);
  for (const auto& t : from_meta) {
    EXPECT_EQ(t.count, 4u) << t.name;
    EXPECT_EQ(t.first_ns, t0);
    EXPECT_EQ(t.last_ns, t1);
  }
  // From the .db3 alone: SQL counts with each topic's own first and last time.
  auto from_sql = openRos2Bag(bag + "/run_0.db3")->topics();
  ASSERT_EQ(from_sql.size(), 7u);
  for (const auto& t : from_sql) {
    EXPECT_EQ(t.count, 4u) << t.name;
    EXPECT_EQ(t.last_ns - t.first_ns, 300000000) << t.name;
    EXPECT_NEAR(t.rateHz(), 10.0, 1e-9) << t.name;
  }
  EXPECT_EQ(from_sql[0].name, "/ground_truth");  // first written
  EXPECT_EQ(from_sql[0].type, "geometry_msgs/msg/PoseStamped");
  EXPECT_EQ(from_sql[0].first_ns, t0 + 6);
  // The metadata.yaml is rosbag2's, version 5.
  const YAML::Node m = YAML::LoadFile(bag + "/metadata.yaml")["rosbag2_bagfile_information"];
  EXPECT_EQ(m["version"].as<int>(), 5);
  EXPECT_EQ(m["storage_identifier"].as<std::string>(), "sqlite3");
  EXPECT_EQ(m["message_count"].as<int>(), 28);
  EXPECT_EQ(m["duration"]["nanoseconds"].as<int64_t>(), t1 - t0);
  EXPECT_EQ(m["starting_time"]["nanoseconds_since_epoch"].as<int64_t>(), t0);
  EXPECT_EQ(m["relative_file_paths"][0].as<std::string>(), "run_0.db3");
  EXPECT_EQ(m["files"][0]["message_count"].as<int>(), 28);
  EXPECT_EQ(m["compression_format"].as<std::string>(), "");
  EXPECT_EQ(m["topics_with_message_count"][0]["topic_metadata"]["serialization_format"].as<std::string>(), "cdr");
}

void sql(sqlite3* db, const std::string& s) {
  char* err = nullptr;
  ASSERT_EQ(sqlite3_exec(db, s.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "") << "\n" << s;
}
void insertMessage(sqlite3* db, int64_t topic_id, int64_t ns, const std::vector<uint8_t>& data) {
  sqlite3_stmt* s = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1, &s, nullptr), SQLITE_OK);
  sqlite3_bind_int64(s, 1, topic_id);
  sqlite3_bind_int64(s, 2, ns);
  sqlite3_bind_blob(s, 3, data.data(), int(data.size()), SQLITE_TRANSIENT);
  EXPECT_EQ(sqlite3_step(s), SQLITE_DONE);
  sqlite3_finalize(s);
}

// A Jazzy-layout bag made with the sqlite3 API: schema 4 (message_definitions, type hashes),
// a std_msgs topic we do not read, one undecodable scan, messages inserted out of time order,
// and a second split file that metadata.yaml lists but that is missing.
TEST(Ros2Bag, ReadsABagWrittenByHandInRosbag2Layout) {
  test::TempDir dir;
  fs::create_directories(dir.file("hand"));
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dir.file("hand/hand_0.db3").c_str(), &db), SQLITE_OK);
  sql(db,
      "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL);"
      "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata TEXT NOT NULL);"
      "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,"
      "serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL,type_description_hash TEXT NOT NULL);"
      "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY,topic_type TEXT NOT NULL,encoding TEXT NOT NULL,"
      "encoded_message_definition TEXT NOT NULL,type_description_hash TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
      "INSERT INTO schema (schema_version, ros_distro) VALUES (4, 'jazzy');"
      "INSERT INTO topics VALUES (3, '/scan', 'sensor_msgs/msg/LaserScan', 'cdr', '', 'RIHS01_aa');"
      "INSERT INTO topics VALUES (7, '/chatter', 'std_msgs/msg/String', 'cdr', '', 'RIHS01_bb');"
      "INSERT INTO topics VALUES (9, '/odom', 'nav_msgs/msg/Odometry', 'cdr', '', 'RIHS01_cc');");
  const auto msgs = everyType(0);
  const auto scan = msg::encodeCdr(msgs[0].second), odom = msg::encodeCdr(msgs[4].second);
  insertMessage(db, 9, 3000, odom);
  insertMessage(db, 3, 1000, scan);
  insertMessage(db, 7, 1500, {0, 1, 0, 0, 6, 0, 0, 0, 'h', 'e', 'l', 'l', 'o', 0});
  insertMessage(db, 3, 2000, {0, 1, 0, 0, 1, 2, 3});  // cut short: undecodable
  insertMessage(db, 7, 2500, {0, 1, 0, 0, 1, 0, 0, 0, 0});
  insertMessage(db, 3, 4000, scan);
  sqlite3_close(db);
  std::ofstream(dir.file("hand/metadata.yaml")) << R"(rosbag2_bagfile_information:
  version: 9
  storage_identifier: sqlite3
  duration:
    nanoseconds: 3000
  starting_time:
    nanoseconds_since_epoch: 1000
  message_count: 6
  topics_with_message_count:
    - topic_metadata:
        name: /scan
        type: sensor_msgs/msg/LaserScan
        serialization_format: cdr
        offered_qos_profiles:
          - history: keep_last
            depth: 10
        type_description_hash: RIHS01_aa
      message_count: 3
  compression_format: ""
  compression_mode: ""
  relative_file_paths:
    - hand_0.db3
    - hand_1.db3
  files: []
  custom_data: ~
  ros_distro: jazzy
)";
  auto r = openRecording(dir.file("hand"));
  const auto got = readAll(*r);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].topic, "/scan");
  EXPECT_EQ(got[0].log_time_ns, 1000);
  expectSame(got[0].message, msgs[0].second);
  EXPECT_EQ(got[1].topic, "/odom");
  EXPECT_EQ(got[1].log_time_ns, 3000);
  expectSame(got[1].message, msgs[4].second);
  EXPECT_EQ(got[2].log_time_ns, 4000);
  const auto& w = r->stats().warnings;
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NE(w[0].find("hand_1.db3, which does not exist"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("/chatter: type std_msgs/msg/String (cdr) is not supported"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("hand_0.db3: topic /scan at t=0.000002000"), std::string::npos) << w[2];
  EXPECT_EQ(r->stats().rejected, 3u);
  EXPECT_EQ(r->stats().messages, 3u);
  // A split file is missing, so topics() counts in the database rather than trust metadata.yaml.
  const auto topics = r->topics();
  ASSERT_EQ(topics.size(), 3u);
  EXPECT_EQ(topics[0].name, "/scan");
  EXPECT_EQ(topics[0].count, 3u);
  EXPECT_EQ(topics[0].first_ns, 1000);
  EXPECT_EQ(topics[0].last_ns, 4000);
  EXPECT_EQ(topics[1].name, "/chatter");
  EXPECT_EQ(topics[1].type, "std_msgs/msg/String");
}

TEST(Ros2Bag, UndecodableMessageIsWarnedAndTheRestRead) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 2);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((bag + "/run_0.db3").c_str(), &db), SQLITE_OK);
  sql(db, "UPDATE messages SET data = X'000100000102' WHERE timestamp = 1700000000000000001");
  sqlite3_close(db);
  auto r = openRecording(bag);
  EXPECT_EQ(readAll(*r).size(), 13u);
  ASSERT_EQ(r->stats().warnings.size(), 1u);
  EXPECT_NE(r->stats().warnings[0].find("topic /points at t=1700000000.000000001"), std::string::npos)
      << r->stats().warnings[0];
}

void expectIoErrorNaming(const std::string& open_path, const std::string& named) {
  try {
    auto r = openRecording(open_path);
    readAll(*r);
    FAIL() << "no IoError for " << open_path;
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
  }
}

TEST(Ros2Bag, CorruptDatabaseThrowsNamingTheFile) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 200);  // many pages
  const std::string db3 = bag + "/run_0.db3";
  std::string bytes;
  {
    std::ifstream in(db3, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 100000u);
  std::ofstream(db3, std::ios::binary) << bytes.substr(0, bytes.size() / 2);  // truncated
  expectIoErrorNaming(bag, db3);
  expectIoErrorNaming(db3, db3);
  std::string garbage(8192, '\0');
  std::mt19937 rng(3);
  for (char& c : garbage) c = static_cast<char>(rng());
  std::ofstream(db3, std::ios::binary) << garbage;  // not a database
  expectIoErrorNaming(bag, db3);
  std::ofstream(db3, std::ios::binary) << "";  // empty
  expectIoErrorNaming(bag, db3);
  std::ofstream(bag + "/metadata.yaml") << "rosbag2_bagfile_information: [unclosed\n";
  expectIoErrorNaming(bag, "metadata.yaml");
}

TEST(Ros2Bag, BitFlippedDatabasesNeverCrash) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 30);
  std::string bytes;
  {
    std::ifstream in(bag + "/run_0.db3", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::mt19937 rng(5);
  int opened = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::string b = bytes;
    const int flips = 1 + trial % 8;
    for (int k = 0; k < flips; ++k) {
      const size_t at = std::uniform_int_distribution<size_t>(0, b.size() - 1)(rng);
      b[at] = static_cast<char>(b[at] ^ (1 << (rng() % 8)));
    }
    const std::string path = dir.file("flipped.db3");
    std::ofstream(path, std::ios::binary) << b;
    try {
      auto r = openRos2Bag(path);
      ++opened;
      readAll(*r);
      r->topics();
      for (const auto& w : r->stats().warnings) EXPECT_NE(w.find(path), std::string::npos) << w;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  EXPECT_GT(opened, 0);
}

TEST(Ros2Bag, OpenRecordingFindsBagsByContent) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 1);
  fs::copy_file(bag + "/run_0.db3", dir.file("renamed.bin"));  // an sqlite file by its header
  auto r = openRecording(dir.file("renamed.bin"));
  EXPECT_EQ(r->format(), "ros2bag");
  EXPECT_EQ(readAll(*r).size(), 7u);
  // A bag directory without metadata.yaml: its .db3 files.
  fs::remove(bag + "/metadata.yaml");
  EXPECT_EQ(readAll(*openRecording(bag)).size(), 7u);
  // rosbag2 with MCAP storage: the one .mcap file is opened as MCAP.
  fs::create_directories(dir.file("mcapbag"));
  {
    auto w = createMcap(dir.file("mcapbag/mcapbag_0.mcap"));
    w->write("/odom", 5, msg::Odometry{});
  }
  std::ofstream(dir.file("mcapbag/metadata.yaml"))
      << "rosbag2_bagfile_information:\n  version: 9\n  storage_identifier: mcap\n"
         "  relative_file_paths:\n    - mcapbag_0.mcap\n";
  EXPECT_EQ(openRecording(dir.file("mcapbag"))->format(), "mcap");
}

TEST(Ros2Bag, WriterRefusesToOverwriteAndTypeChanges) {
  test::TempDir dir;
  const std::string bag = writeBag(dir, "run", 1);
  EXPECT_THROW(createRos2Bag(bag), IoError);
  auto w = createRos2Bag(dir.file("other"));
  w->write("/odom", 1, msg::Odometry{});
  EXPECT_THROW(w->write("/odom", 2, msg::PoseStamped{}), IoError);
  w->close();
  auto r = openRecording(dir.file("other"));
  EXPECT_EQ(readAll(*r).size(), 1u);
  // An empty bag is a valid bag.
  createRos2Bag(dir.file("empty"))->close();
  auto e = openRecording(dir.file("empty"));
  EXPECT_TRUE(e->topics().empty());
  EXPECT_EQ(readAll(*e).size(), 0u);
}

}  // namespace
}  // namespace polyloc
