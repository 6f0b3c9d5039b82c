// `polyloc ctl` end to end against the control server with the fake handler in this process:
// what a person types, what comes back (text and --json), and the errors.
#include "protocol_fixtures.hpp"
#include "run_command.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_protocol_cli {

using namespace polyloc::protocol;
using polyloc::protocol::fake::TestServer;


using CtlRun = polyloc::test::CommandRun;  // out: stdout and stderr

CtlRun ctl(const TestServer& t, const std::string& args) {
  return polyloc::test::runCommand(std::string(POLYLOC_CLI) + " ctl --port " + std::to_string(t.server.port()) + " " +
                                   args + " 2>&1");
}

nlohmann::json ctlJson(const TestServer& t, const std::string& args) {
  const CtlRun r = ctl(t, "--json " + args);
  EXPECT_EQ(r.rc, 0) << r.out;
  return nlohmann::json::parse(r.out);
}


TEST(ProtocolCli, QueriesAsJson) {
  TestServer t;
  auto j = ctlJson(t, "ping");
  EXPECT_EQ(j["command"], "PING");
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(j["server"], "127.0.0.1:" + std::to_string(t.server.port()));
  j = ctlJson(t, "getpose");
  EXPECT_NEAR(j["pose"]["x_m"].get<double>(), 1.25, 1e-6);
  EXPECT_NEAR(j["pose"]["yaw_deg"].get<double>(), 28.6479, 1e-3);
  EXPECT_EQ(j["pose_status"], "tracking");
  EXPECT_EQ(j["covariance"].size(), 36u);
  EXPECT_EQ(j["particles"], 2000);
  j = ctlJson(t, "scanners");
  ASSERT_EQ(j["scanners"].size(), 3u);
  EXPECT_EQ(j["scanners"][1]["name"], "front");
  j = ctlJson(t, "scan 1");
  EXPECT_EQ(j["beams"], 181);
  EXPECT_TRUE(j["ranges_m"][9].is_null());  // no return
  j = ctlJson(t, "tracks");
  EXPECT_EQ(j["tracks"][0]["id"], 7);
  j = ctlJson(t, "status");
  EXPECT_EQ(j["inputs"][1]["silent"], true);
  EXPECT_EQ(j["cycles"], 1000);
}

TEST(ProtocolCli, Commands) {
  TestServer t;
  EXPECT_EQ(ctlJson(t, "setca 0")["status"], "ok");
  EXPECT_EQ(ctlJson(t, "getca")["collision_avoidance"], false);
  EXPECT_EQ(ctlJson(t, "scan 0")["status"], "collision_avoidance_off");  // a warning: exit 0
  EXPECT_EQ(ctlJson(t, "setpose -1.5 2 90 0.2 5")["status"], "ok");
  {
    auto l = t.handler.lock();
    ASSERT_TRUE(t.handler.last_seed);
    EXPECT_NEAR(t.handler.last_seed->x, -1.5, 1e-6);
    EXPECT_NEAR(t.handler.last_seed->yaw, M_PI / 2, 1e-6);
    EXPECT_NEAR(*t.handler.last_seed->sigma_yaw_rad, 5 * M_PI / 180, 1e-6);
  }
  EXPECT_EQ(ctlJson(t, "getpose")["pose_status"], "uncertain");
  EXPECT_EQ(ctlJson(t, "global")["status"], "ok");
  const CtlRun text = ctl(t, "status");
  EXPECT_EQ(text.rc, 0);
  EXPECT_NE(text.out.find("cycle_p99_ms: 9.5"), std::string::npos) << text.out;
}

TEST(ProtocolCli, ErrorsNameWhatWasWrong) {
  TestServer t;
  t.handler.lock(), t.handler.pose_status = PoseStatus::Initialising;  // no pose yet
  CtlRun r = ctl(t, "getpose");
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.out.find("GETPOSECOVARIANCE: not_available (-4)"), std::string::npos) << r.out;
  r = ctl(t, "scan 7");
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.out.find("bad_argument"), std::string::npos) << r.out;
  r = ctl(t, "setca 2");
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.out.find("'2' is not 0 or 1"), std::string::npos) << r.out;
  r = ctl(t, "setpose 1 x 3");
  EXPECT_EQ(r.rc, 1);
  EXPECT_NE(r.out.find("Y: 'x' is not a number"), std::string::npos) << r.out;
  EXPECT_EQ(t.server.counters().frames, 2u);  // usage errors never reached the server
}

}  // namespace polyloc::t_protocol_cli
