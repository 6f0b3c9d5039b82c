// The live view's messages (service/live/live_messages.hpp), decoded back as a client does;
// the `polylocd.live` config section; the server's start-up errors. The protocol end to end,
// with a Foxglove client and a browser, is tests/cli/live_view.sh.
#include "fixtures.hpp"
#include "live/foxglove_server.hpp"
#include "live/live_messages.hpp"
#include "pipeline/daemon_config.hpp"

#include <polyloc/io/cdr.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/map/slice.hpp>
#include <polyloc/mcl/particles.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_live {

using namespace polyloc;
using namespace polyloc::live;
using json = nlohmann::json;


json parse(const Bytes& b) { return json::parse(std::string(b.begin(), b.end())); }

template <class T>
T decode(const std::string& type, const Bytes& b) {
  return std::get<T>(msg::decodeCdr(type, b));
}


TEST(LiveMessages, PoseWithItsCovarianceInRosOrder) {
  MclEstimate e;
  e.stamp_ns = 1'700'000'000'123'456'789;
  e.pose = Pose::fromXYZRPY(3.25, -1.5, 0.02, 0.01, -0.02, 1.2);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) e.covariance(r, c) = r == c ? 0.01 * (r + 1) : 0.001 * (r - c);
  const auto m = decode<msg::PoseWithCovarianceStamped>("geometry_msgs/msg/PoseWithCovarianceStamped", poseCdr(e));
  EXPECT_EQ(msg::toNs(m.header.stamp), e.stamp_ns);
  EXPECT_EQ(m.header.frame_id, "map");
  EXPECT_TRUE(fromMsgPose(m.pose.pose).isApprox(e.pose, 1e-12));
  EXPECT_DOUBLE_EQ(m.pose.covariance[0], 0.01);       // x x
  EXPECT_DOUBLE_EQ(m.pose.covariance[35], 0.06);      // yaw yaw
  EXPECT_DOUBLE_EQ(m.pose.covariance[6 * 5 + 0], 0.005);  // yaw x: row-major, not transposed
}

TEST(LiveMessages, ParticlesAreSubsampledWithTheirWeights) {
  ParticleSet p;
  resizeParticles(p, 2000);
  for (size_t i = 0; i < 2000; ++i) {
    setParticle(p, i, Pose::planar(0.001 * double(i), 2.0, 0.5));
    p.logw[i] = i == 8 ? 0.0 : -1.0;  // particle 8 the heaviest
  }
  const auto c = decode<msg::PointCloud2>("sensor_msgs/msg/PointCloud2", particlesCdr(42, p, 500));
  ASSERT_EQ(c.fields.size(), 5u);
  EXPECT_EQ(c.fields[3].name, "yaw");
  EXPECT_EQ(c.fields[4].name, "weight");
  ASSERT_EQ(c.width, 500u);  // every 4th
  ASSERT_EQ(c.data.size(), 500u * 20);
  float v[5];
  std::memcpy(v, c.data.data() + 2 * 20, sizeof v);  // the third point is particle 8
  EXPECT_FLOAT_EQ(v[0], 0.008f);
  EXPECT_FLOAT_EQ(v[1], 2.0f);
  EXPECT_NEAR(v[3], 0.5f, 1e-6);
  EXPECT_FLOAT_EQ(v[4], 1.0f);
  std::memcpy(v, c.data.data() + 20, sizeof v);
  EXPECT_NEAR(v[4], std::exp(-1.0), 1e-6);
  // Fewer particles than the limit: all of them.
  EXPECT_EQ(decode<msg::PointCloud2>("sensor_msgs/msg/PointCloud2", particlesCdr(42, p, 5000)).width, 2000u);
}

TEST(LiveMessages, TransformsComposeToThePose) {
  const Pose map_T_odom = Pose::fromXYZRPY(0.3, -0.2, 0, 0, 0, 0.1), pose = Pose::planar(4.0, 2.0, 1.0);
  const auto tf = decode<msg::TFMessage>("tf2_msgs/msg/TFMessage", tfCdr(7, map_T_odom, map_T_odom.inverse() * pose));
  ASSERT_EQ(tf.transforms.size(), 2u);
  EXPECT_EQ(tf.transforms[0].header.frame_id, "map");
  EXPECT_EQ(tf.transforms[0].child_frame_id, "odom");
  EXPECT_EQ(tf.transforms[1].child_frame_id, "base_link");
  auto of = [](const msg::Transform& t) { return fromMsgPose({{t.translation.x, t.translation.y, t.translation.z}, t.rotation}); };
  EXPECT_TRUE((of(tf.transforms[0].transform) * of(tf.transforms[1].transform)).isApprox(pose, 1e-9));
}

TEST(LiveMessages, SceneHoldsEveryTriangleByLabel) {
  const Mesh room = test::boxRoom(3, 2, 2.5, 0.1);
  const json s = parse(sceneOfMesh(room));
  ASSERT_EQ(s["entities"].size(), 1u);
  const json& e = s["entities"][0];
  EXPECT_EQ(e["frame_id"], "map");
  size_t points = 0;
  for (const json& t : e["triangles"]) {
    EXPECT_EQ(t["points"].size() % 3, 0u);
    points += t["points"].size();
    EXPECT_GT(t["color"]["a"].get<double>(), 0.0);
  }
  EXPECT_EQ(points, 3 * room.numTriangles());
  EXPECT_EQ(e["triangles"].size(), 3u);  // floor, ceiling, wall
}

TEST(LiveMessages, MapSliceOfARoom) {
  const Mesh room = test::boxRoom(3, 2, 2.5, 0.1);
  const json s = parse(mapSliceJson(room, 0.3f));
  EXPECT_EQ(s["segments"].size(), 4 * s["segment_label"].size());
  EXPECT_EQ(s["segment_label"].size(), sliceMesh(room, 0.3f).size());
  const auto b = s["bounds"].get<std::vector<double>>();
  ASSERT_EQ(b.size(), 4u);
  EXPECT_NEAR(b[0], -3.1, 1e-3);  // the walls' outer faces
  EXPECT_NEAR(b[3], 2.1, 1e-3);
  for (const json& l : s["segment_label"]) EXPECT_EQ(s["labels"][l.get<size_t>()], "wall");
}

TEST(LiveMessages, ScansVrsTracksAndDepth) {
  const std::vector<float> r{1.f, 2.f, std::numeric_limits<float>::infinity()};
  const auto s = decode<msg::LaserScan>("sensor_msgs/msg/LaserScan", laserScanCdr(5, "s300", {-1.f, 0.5f, 0.05f, 30.f}, r));
  EXPECT_EQ(s.header.frame_id, "s300");
  EXPECT_FLOAT_EQ(s.angle_max, 0.f);  // min + (n - 1) increment, as ROS
  EXPECT_EQ(s.ranges.size(), 3u);

  VirtualScan v;
  v.stamp_ns = 9, v.angle_min = -float(M_PI), v.angle_increment = float(M_PI) / 2, v.range_max = 8;
  v.ranges = {1, 2, 3, 4};
  const auto vs = decode<msg::LaserScan>("sensor_msgs/msg/LaserScan", vrsCdr(v));
  EXPECT_EQ(vs.header.frame_id, "base_link");
  EXPECT_FLOAT_EQ(vs.angle_min, v.angleOf(0));  // segment centres
  EXPECT_EQ(vs.ranges, v.ranges);

  polyloc_tracks t{};
  t.stamp_ns = 11, t.count = 2;
  t.tracks[0] = {4, 1, 1.0, 2.0, 0.5, -0.25, {0.01, 0, 0, 0.01}};
  t.tracks[1] = {9, 0, -1.0, 0.0, 0.0, 0.0, {0.1, 0, 0, 0.1}};
  const auto ta = decode<msg::TrackArray>("polyloc_msgs/msg/TrackArray", tracksCdr(t));
  ASSERT_EQ(ta.tracks.size(), 2u);
  EXPECT_EQ(ta.tracks[0].id, 4u);
  EXPECT_DOUBLE_EQ(ta.tracks[0].vy, -0.25);
  EXPECT_EQ(ta.tracks[1].status, 0);

  BeamSet beams;
  beams.push(1, 0, 0), beams.push(0, 1, 0), beams.push(0, 0.6f, 0.8f), beams.push(0, 0, 1);
  beams.range_min = 0.1f, beams.range_max = 10.f;
  const std::vector<float> lidar{2.f, std::numeric_limits<float>::quiet_NaN(), 5.f, 50.f};  // NaN, beyond range_max: none
  const auto lc = decode<msg::PointCloud2>("sensor_msgs/msg/PointCloud2", rangesCloudCdr(15, "vlp16", beams, lidar));
  EXPECT_EQ(lc.header.frame_id, "vlp16");
  ASSERT_EQ(lc.width, 2u);
  float q[6];
  std::memcpy(q, lc.data.data(), sizeof q);
  EXPECT_FLOAT_EQ(q[0], 2.f);
  EXPECT_FLOAT_EQ(q[4], 3.f);
  EXPECT_FLOAT_EQ(q[5], 4.f);

  DepthFilterResult d;
  d.x = {1, 2}, d.y = {0, 0.5}, d.z = {0.3, 0.4};
  const auto c = decode<msg::PointCloud2>("sensor_msgs/msg/PointCloud2", depthCdr(13, d));
  EXPECT_EQ(c.header.frame_id, "base_link");
  ASSERT_EQ(c.width, 2u);
  float p[3];
  std::memcpy(p, c.data.data() + 12, sizeof p);
  EXPECT_FLOAT_EQ(p[1], 0.5f);
}

TEST(LiveMessages, TopViewAndHealth) {
  TopView v;
  v.stamp_ns = 77, v.have_pose = true;
  v.pose.pose = Pose::planar(1.2345, -2, 0.5);
  v.pose.covariance(0, 0) = 0.04;
  v.particles = {1, 2, 0.1f};
  v.vrs = {3, 4};
  v.tracks.push_back({5, 1, 1, 1, 0.2, 0, {}});
  v.status = "tracking";
  const json j = parse(topViewJson(v));
  EXPECT_EQ(j["stamp_ns"], 77);
  EXPECT_DOUBLE_EQ(j["pose"]["x"].get<double>(), 1.235);  // millimetres
  EXPECT_DOUBLE_EQ(j["pose"]["cov_xx"].get<double>(), 0.04);
  EXPECT_EQ(j["particles"].size(), 3u);
  EXPECT_EQ(j["tracks"][0]["id"], 5);
  EXPECT_TRUE(j["tracks"][0]["confirmed"].get<bool>());
  v.have_pose = false;
  EXPECT_TRUE(parse(topViewJson(v))["pose"].is_null());

  polyloc_health h{};
  h.poses = 12, h.inputs = 2;
  h.input[1].rejected_nan = 3;
  ServerStats s;
  s.clients = 2, s.messages_dropped = 40, s.disconnected_slow = 1;
  const json k = parse(healthJson(h, {"odom", "scan/front"}, s));
  EXPECT_EQ(k["poses"], 12);
  EXPECT_EQ(k["inputs"][1]["name"], "scan/front");
  EXPECT_EQ(k["inputs"][1]["rejected_nan"], 3);
  EXPECT_EQ(k["viewers"]["messages_dropped"], 40);
  EXPECT_EQ(k["viewers"]["disconnected_slow"], 1);
}

TEST(LiveMessages, ChannelsCarryTheirSchemas) {
  const ChannelSpec c = cdrChannel("/pose", "geometry_msgs/msg/PoseWithCovarianceStamped");
  EXPECT_EQ(c.encoding, "cdr");
  EXPECT_EQ(c.schema_encoding, "ros2msg");
  EXPECT_NE(c.schema.find("MSG: geometry_msgs/PoseWithCovariance"), std::string::npos);
  const ChannelSpec j = jsonChannel("/map", "foxglove.SceneUpdate", true);
  EXPECT_TRUE(j.latched);
  EXPECT_EQ(json::parse(j.schema)["title"], "foxglove.SceneUpdate");
  EXPECT_THROW(jsonChannel("/x", "foxglove.Nothing"), std::logic_error);
}

TEST(LiveConfig, DefaultsValuesAndErrors) {
  auto parseLive = [](const std::string& text) {
    return pipeline::parseDaemonConfig(ConfigMap::parse("polylocd:\n" + text, "t.yaml").map("polylocd")).live;
  };
  const LiveConfig d = parseLive("  instance: x\n");
  EXPECT_EQ(d.port, 8765);
  EXPECT_EQ(d.address, "127.0.0.1");
  const LiveConfig c = parseLive("  live: {port: 0, address: 0.0.0.0, max_clients: 2, max_queue: 0.5, stall_timeout: 1, particles: 100}\n");
  EXPECT_EQ(c.port, 0);
  EXPECT_EQ(c.address, "0.0.0.0");
  EXPECT_EQ(c.max_clients, 2);
  EXPECT_DOUBLE_EQ(c.max_queue_mib, 0.5);
  EXPECT_EQ(c.particles, 100u);
  auto fails = [&](const std::string& text, const std::string& needle) {
    try {
      parseLive(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("t.yaml:2"), std::string::npos) << e.what();
    }
  };
  fails("  live: {address: localhost.example}\n", "not an IP address");
  fails("  live: {port: 70000}\n", "port");
  fails("  live: {max_clients: 0}\n", "max_clients");
  fails("  live: {portt: 1}\n", "portt");
}

TEST(FoxgloveServer, PortInUseIsNamedAndAnyFreePortWorks) {
  ServerConfig cfg;
  cfg.port = 0;
  FoxgloveServer a(cfg);
  const uint32_t ch = a.addChannel(jsonChannel("/polyloc/health", "polyloc.Health"));
  EXPECT_FALSE(a.subscribed(ch));  // before start
  a.start();
  ASSERT_GT(a.port(), 0);
  EXPECT_FALSE(a.subscribed(ch));
  a.publish(ch, 1, Bytes{'{', '}'});  // nobody listens (what reaches clients: test_live_server.cpp)
  EXPECT_THROW(a.addChannel(jsonChannel("/x", "polyloc.Health")), std::logic_error);

  ServerConfig same = cfg;
  same.port = a.port();
  FoxgloveServer b(same);
  try {
    b.start();
    ADD_FAILURE() << "a second server on the same port started";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(a.port())), std::string::npos) << e.what();
  }
  // HTTP on the same port: the page (none configured here: 404), read with a plain socket.
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET, addr.sin_port = htons(a.port());
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  const std::string req = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";
  ASSERT_EQ(write(fd, req.data(), req.size()), ssize_t(req.size()));
  char buf[256] = {};
  ASSERT_GT(read(fd, buf, sizeof buf - 1), 0);
  close(fd);
  EXPECT_EQ(std::string(buf).rfind("HTTP/1.1 404", 0), 0u) << buf;
  a.stop();
  a.stop();  // idempotent
  EXPECT_EQ(a.stats().http_requests, 1u);
}

}  // namespace polyloc::t_live
