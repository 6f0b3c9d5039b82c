// The control server over real loopback sockets with the fake handler: every command's reply,
// bad requests, and the handler's failures.
#include "protocol_fixtures.hpp"

#include "protocol/messages.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_protocol_server {

using namespace polyloc;
using namespace polyloc::protocol;
using polyloc::protocol::fake::eventually;
using polyloc::protocol::fake::TestServer;


Frame ok(Client& c, uint32_t command, const std::vector<uint32_t>& data = {}, Status want = Status::Ok) {
  Frame r = c.call(command, data);
  EXPECT_EQ(r.command, replyId(command)) << commandName(command);
  EXPECT_EQ(replyStatus(r), want) << commandName(command) << ": " << toString(replyStatus(r));
  return r;
}

uint32_t f32(float v) { return std::bit_cast<uint32_t>(v); }


TEST(ProtocolServer, PingEchoesAndCheckProtocol) {
  TestServer t;
  auto c = t.connect();
  EXPECT_EQ(ok(*c, cmd::PING).data, (std::vector<uint32_t>{0}));
  EXPECT_EQ(ok(*c, cmd::PING, {5, 6}).data, (std::vector<uint32_t>{0, 5, 6}));
  EXPECT_EQ(ok(*c, cmd::CHECKPROTOCOL).data, (std::vector<uint32_t>{0, kProtocolVersion}));
  ok(*c, cmd::CHECKPROTOCOL, {0x00010000});
  ok(*c, cmd::CHECKPROTOCOL, {0x00010005}, Status::NewerMinorVersion);
  ok(*c, cmd::CHECKPROTOCOL, {0x00020000}, Status::VersionMismatch);
}

TEST(ProtocolServer, Pose) {
  TestServer t;
  auto c = t.connect();
  Frame r = ok(*c, cmd::GETPOSE);
  auto p = decodePlanarPose(replyData(r));
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->pose.x(), 1.25, 1e-6);
  EXPECT_NEAR(p->pose.y(), -2.5, 1e-6);
  EXPECT_NEAR(p->pose.yaw(), 0.5, 1e-6);
  EXPECT_EQ(p->stamp_ns, 1'700'000'000'123'456'789);

  r = ok(*c, cmd::GETPOSECOVARIANCE);
  p = decodePoseCovariance(replyData(r));
  ASSERT_TRUE(p);
  EXPECT_EQ(p->status, PoseStatus::Tracking);
  EXPECT_NEAR(p->covariance(5, 5), 0.06, 1e-7);
  EXPECT_NEAR(p->covariance(1, 0), 0.002, 1e-7);
  EXPECT_NEAR(p->ess, 812.5, 1e-3);
  EXPECT_EQ(p->particles, 2000u);

  t.handler.lock(), t.handler.pose_status = PoseStatus::Lost;
  ok(*c, cmd::GETPOSE, {}, Status::PoseLost);
  t.handler.lock(), t.handler.pose_status = PoseStatus::Initialising;
  EXPECT_EQ(ok(*c, cmd::GETPOSE, {}, Status::NotAvailable).data.size(), 1u);  // no data after an error
  ok(*c, cmd::GETPOSECOVARIANCE, {}, Status::NotAvailable);
}

TEST(ProtocolServer, SetPoseAndGlobalLocalization) {
  TestServer t;
  auto c = t.connect();
  ok(*c, cmd::SETPOSE, encodeSeed({4, 5, 1.0, 0.3, 0.2}));
  {
    auto l = t.handler.lock();
    ASSERT_TRUE(t.handler.last_seed);
    EXPECT_NEAR(t.handler.last_seed->x, 4, 1e-6);
    EXPECT_NEAR(*t.handler.last_seed->sigma_yaw_rad, 0.2, 1e-6);
  }
  ok(*c, cmd::GETPOSE, {}, Status::PoseUncertain);  // the fake's state after a seed
  ok(*c, cmd::SETPOSE, encodeSeed({1, 2, 3, {}, {}}));
  EXPECT_FALSE((t.handler.lock(), t.handler.last_seed->sigma_xy_m));
  ok(*c, cmd::SETPOSE, encodeSeed({5000, 0, 0, {}, {}}), Status::BadArgument);  // the handler's no
  const float nan = std::numeric_limits<float>::quiet_NaN();
  ok(*c, cmd::SETPOSE, {f32(nan), 0, 0}, Status::BadArgument);
  ok(*c, cmd::SETPOSE, {0, 0, 0, f32(-1.0f), 0}, Status::BadArgument);
  ok(*c, cmd::SETPOSE, {0, 0}, Status::BadSize);
  ok(*c, cmd::GLOBALLOCALIZATION);
  EXPECT_EQ((t.handler.lock(), t.handler.global_calls), 1);
  ok(*c, cmd::GETPOSE, {}, Status::NotAvailable);
}

TEST(ProtocolServer, ScannersAndScans) {
  TestServer t;
  auto c = t.connect();
  EXPECT_EQ(ok(*c, cmd::GETNUMSCANNERS).data, (std::vector<uint32_t>{0, 3}));
  auto mount = decodeMount(replyData(ok(*c, cmd::GETSCANNERPOSE, {2})));
  ASSERT_TRUE(mount);
  EXPECT_NEAR(mount->x(), -0.3, 1e-6);
  EXPECT_NEAR(std::abs(mount->yaw()), M_PI, 1e-6);
  ok(*c, cmd::GETSCANNERPOSE, {3}, Status::BadArgument);
  const auto list = decodeScanners(replyData(ok(*c, cmd::GETSCANNERS)));
  ASSERT_TRUE(list && list->size() == 3);
  EXPECT_EQ((*list)[0].name, "vrs");
  EXPECT_EQ((*list)[1].name, "front");
  EXPECT_NEAR((*list)[1].mount.z(), 0.25, 1e-6);

  for (uint32_t i = 0; i < 3; ++i) {
    const auto s = decodeScan(replyData(ok(*c, cmd::GETSCANRADIALSCANNER, {i})));
    ASSERT_TRUE(s);
    ASSERT_EQ(s->ranges.size(), 181u);
    EXPECT_EQ(s->stamp_ns, 1'700'000'000'000'000'000 + i);
    EXPECT_NEAR(s->angles.front(), -M_PI / 2, 1e-6);
    EXPECT_NEAR(s->ranges[0], i + 1.0, 1e-6);
    EXPECT_TRUE(std::isinf(s->ranges[9]));
  }
  ok(*c, cmd::GETSCANRADIALSCANNER, {3}, Status::BadArgument);
  ok(*c, cmd::GETSCANRADIALSCANNER, {}, Status::BadSize);
  t.handler.lock(), t.handler.have_scans = false;
  ok(*c, cmd::GETSCANRADIALSCANNER, {1}, Status::NotAvailable);
}

TEST(ProtocolServer, CollisionAvoidanceSwitchesVrsPublication) {
  TestServer t;
  auto c = t.connect();
  EXPECT_EQ(ok(*c, cmd::GETCOLLISIONAVOIDANCE).data, (std::vector<uint32_t>{0, 1}));
  ok(*c, cmd::SETCOLLISIONAVOIDANCE, {0});
  EXPECT_EQ(ok(*c, cmd::GETCOLLISIONAVOIDANCE).data, (std::vector<uint32_t>{0, 0}));
  ok(*c, cmd::GETSCANRADIALSCANNER, {0}, Status::CollisionAvoidanceOff);  // the VRS, qualified
  ok(*c, cmd::GETSCANRADIALSCANNER, {1});                                 // raw scans as ever
  ok(*c, cmd::SETCOLLISIONAVOIDANCE, {2}, Status::BadArgument);
  ok(*c, cmd::SETCOLLISIONAVOIDANCE, {1});
  EXPECT_TRUE((t.handler.lock(), t.handler.collision_avoidance));
}

TEST(ProtocolServer, TracksAndStatus) {
  TestServer t;
  auto c = t.connect();
  const auto tracks = decodeTracks(replyData(ok(*c, cmd::GETTRACKS)));
  ASSERT_TRUE(tracks && tracks->tracks.size() == 2);
  EXPECT_EQ(tracks->tracks[0].id, 7u);
  EXPECT_NEAR(tracks->tracks[0].vy, -0.25, 1e-6);
  EXPECT_FALSE(tracks->tracks[1].confirmed);
  const auto h = decodeHealth(replyData(ok(*c, cmd::GETSTATUS)));
  ASSERT_TRUE(h && h->inputs.size() == 2);
  EXPECT_EQ(h->cycles, 1000u);
  EXPECT_NEAR(h->cycle_p99_ms, 9.5, 1e-6);
  EXPECT_EQ(h->inputs[1].name, "odom");
  EXPECT_TRUE(h->inputs[1].silent);
  EXPECT_EQ(h->inputs[0].rejected, 3u);
}

TEST(ProtocolServer, UnknownCommandsSizesAndHandlerFailures) {
  TestServer t;
  auto c = t.connect();
  ok(*c, 0x00030000, {}, Status::UnknownCommand);
  ok(*c, 0x001fffff, {}, Status::UnknownCommand);
  ok(*c, 0x80000000, {}, Status::UnknownCommand);  // a reply sent as a request
  ok(*c, cmd::GETPOSE, {1}, Status::BadSize);
  ok(*c, cmd::GETNUMSCANNERS, {1}, Status::BadSize);
  t.handler.lock(), t.handler.throw_on_tracks = true;
  ok(*c, cmd::GETTRACKS, {}, Status::Internal);
  ok(*c, cmd::PING);  // the server goes on
  const auto n = t.server.counters();
  EXPECT_EQ(n.unknown_command, 3u);
  EXPECT_EQ(n.bad_request, 2u);
  EXPECT_EQ(n.handler_failures, 1u);
  EXPECT_EQ(n.frames, 7u);
  EXPECT_EQ(n.accepted, 1u);
}

TEST(ProtocolServer, BindErrorsNameTheAddress) {
  TestServer t;
  fake::FakeHandler h;
  ServerConfig same;
  same.port = t.server.port();
  Server second(same, h);
  try {
    second.start();
    FAIL() << "bound a port in use";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(same.port)), std::string::npos) << e.what();
  }
  ServerConfig bad;
  bad.bind_address = "not-an-address";
  Server third(bad, h);
  EXPECT_THROW(third.start(), std::runtime_error);
  EXPECT_THROW(t.server.start(), std::logic_error);
}

TEST(ProtocolServer, SettingsThatCannotWorkAreRefusedByName) {
  fake::FakeHandler h;
  ServerConfig cfg;
  cfg.max_clients = 0;
  Server s(cfg, h);
  try {
    s.start();
    FAIL() << "started with max_clients 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_clients"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(s.running());
}

}  // namespace polyloc::t_protocol_server
