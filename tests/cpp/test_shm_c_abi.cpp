// libpolyloc_client through its C ABI: status codes and messages, writing inputs, reading
// outputs, waits, staleness and re-attach; and the example controller of the docs, compiled as
// C, run against a segment with a stand-in daemon.
#include <polyloc_client.h>

#include "shm_fixtures.hpp"

#include <polyloc/geometry/pose.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <thread>
#include <tuple>

namespace polyloc::t_shm_c_abi {  // the file's own: the suite is compiled in batches (unity build)
namespace {

using shm::Reader;
using shm::Segment;
using shm::Writer;

std::string lastError() { return polyloc_last_error(); }

TEST(ShmCAbi, AttachErrorsHaveCodesAndMessages) {
  test::ShmName name;
  polyloc_client* c = nullptr;
  EXPECT_EQ(polyloc_attach(name.str().c_str(), &c), POLYLOC_ERR_NOT_FOUND);
  EXPECT_EQ(c, nullptr);
  EXPECT_NE(lastError().find("does not exist"), std::string::npos) << lastError();
  EXPECT_EQ(polyloc_attach(nullptr, &c), POLYLOC_ERR_ARGUMENT);
  EXPECT_EQ(polyloc_attach("bad/name", &c), POLYLOC_ERR_ARGUMENT);

  auto seg = Segment::create(name, test::rigChannels());
  EXPECT_EQ(polyloc_attach(name.str().c_str(), &c), POLYLOC_ERR_NOT_READY);
  seg.ready();
  reinterpret_cast<polyloc_shm_header*>(seg.base())->abi_version = POLYLOC_SHM_ABI_VERSION + 1;
  EXPECT_EQ(polyloc_attach(name.str().c_str(), &c), POLYLOC_ERR_ABI);
  EXPECT_NE(lastError().find("has ABI version 3; this client speaks 2"), std::string::npos) << lastError();
  EXPECT_STREQ(polyloc_status_name(POLYLOC_ERR_ABI), "ABI version mismatch");
  reinterpret_cast<polyloc_shm_header*>(seg.base())->abi_version = POLYLOC_SHM_ABI_VERSION;
  ASSERT_EQ(polyloc_attach(name.str().c_str(), &c), POLYLOC_OK);
  EXPECT_EQ(polyloc_generation(c), seg.generation());
  EXPECT_EQ(polyloc_abi_version(), POLYLOC_SHM_ABI_VERSION);
  EXPECT_EQ(polyloc_channel_count(c), 7);
  EXPECT_EQ(polyloc_channel(c, "nope"), POLYLOC_ERR_NOT_FOUND);
  EXPECT_NE(lastError().find("no channel 'nope'"), std::string::npos) << lastError();
  polyloc_channel_desc d;
  EXPECT_EQ(polyloc_channel_info(c, 99, &d), POLYLOC_ERR_ARGUMENT);
  polyloc_detach(c);
  polyloc_detach(nullptr);
}

TEST(ShmCAbi, WritesInputsAndReadsOutputs) {
  test::ShmName name;
  auto seg = Segment::create(name, test::rigChannels());
  seg.ready();
  polyloc_client* c = nullptr;
  ASSERT_EQ(polyloc_attach(name.str().c_str(), &c), POLYLOC_OK);
  const int scan = polyloc_channel(c, "scan/front"), odom = polyloc_channel(c, "odom"),
            depth = polyloc_channel(c, "depth/tof"), pose = polyloc_channel(c, "pose");
  ASSERT_GE(scan, 0);
  Reader rs(seg, scan), ro(seg, odom), rd(seg, depth);

  std::vector<float> ranges(541, 3.5f);
  EXPECT_EQ(polyloc_write_ranges(c, scan, 77, ranges.data(), 541), POLYLOC_OK);
  EXPECT_EQ(polyloc_write_ranges(c, scan, 78, ranges.data(), 540), POLYLOC_ERR_SIZE);
  EXPECT_NE(lastError().find("540 ranges, channel 'scan/front' has 541 beams"), std::string::npos) << lastError();
  EXPECT_EQ(polyloc_write_ranges(c, odom, 78, ranges.data(), 541), POLYLOC_ERR_KIND);
  EXPECT_EQ(polyloc_write_ranges(c, pose, 78, ranges.data(), 541), POLYLOC_ERR_KIND);
  const double p7[7] = {1, 2, 0, 1, 0, 0, 0}, tw[3] = {0.5, 0, 0.1};
  EXPECT_EQ(polyloc_write_odometry(c, odom, 79, p7, tw), POLYLOC_OK);
  EXPECT_EQ(polyloc_write_odometry(c, odom, 80, nullptr, tw), POLYLOC_ERR_ARGUMENT);
  std::vector<float> dep(64 * 50, 1.f), amp(64 * 50, 100.f);
  EXPECT_EQ(polyloc_write_depth(c, depth, 81, dep.data(), amp.data(), 64, 50), POLYLOC_OK);
  EXPECT_EQ(polyloc_write_depth(c, depth, 82, dep.data(), nullptr, 64, 50), POLYLOC_OK);
  EXPECT_EQ(polyloc_write_depth(c, depth, 83, dep.data(), nullptr, 32, 50), POLYLOC_ERR_SIZE);

  std::vector<uint8_t> p;
  auto f = rs.next(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->stamp_ns, 77);
  EXPECT_EQ(f->size, 16u + 541 * 4);
  const auto* r = reinterpret_cast<const polyloc_ranges*>(p.data());
  EXPECT_EQ(r->count, 541u);
  EXPECT_EQ(r->ranges[540], 3.5f);
  f = ro.next(p);
  ASSERT_TRUE(f);
  const auto* o = reinterpret_cast<const polyloc_odometry*>(p.data());
  EXPECT_EQ(o->y, 2.0);
  EXPECT_EQ(o->vx, 0.5);
  EXPECT_EQ(o->stamp_ns, 79);
  f = rd.next(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->size, 24u + 2 * 64 * 50 * 4);
  f = rd.next(p);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->size, 24u + 64 * 50 * 4);
  EXPECT_EQ(reinterpret_cast<const polyloc_depth*>(p.data())->has_amplitude, 0u);

  // Outputs: nothing yet, then the newest and the next.
  polyloc_pose out{};
  polyloc_frame_info info{};
  EXPECT_EQ(polyloc_read_pose(c, &out, &info), POLYLOC_NO_DATA);
  EXPECT_EQ(polyloc_next_pose(c, &out, &info), POLYLOC_NO_DATA);
  EXPECT_EQ(polyloc_wait(c, pose, 0), POLYLOC_TIMEOUT);
  Writer wp(seg, seg.find("pose"));
  for (int i = 1; i <= 3; ++i) {
    polyloc_pose q{};
    q.x = i;
    wp.write(&q, sizeof q, i);
  }
  EXPECT_EQ(polyloc_wait(c, pose, 1'000'000), POLYLOC_OK);
  EXPECT_EQ(polyloc_wait_spin(c, pose, 1'000'000, 10'000), POLYLOC_OK);
  ASSERT_EQ(polyloc_next_pose(c, &out, &info), POLYLOC_OK);
  EXPECT_EQ(out.x, 1.0);
  EXPECT_EQ(info.frame, 0u);
  ASSERT_EQ(polyloc_read_pose(c, &out, &info), POLYLOC_OK);
  EXPECT_EQ(out.x, 3.0);
  EXPECT_EQ(info.stamp_ns, 3);
  EXPECT_EQ(polyloc_next_pose(c, &out, &info), POLYLOC_NO_DATA);
  ASSERT_EQ(polyloc_read_pose(c, &out, nullptr), POLYLOC_OK);   // the newest again
  EXPECT_EQ(out.x, 3.0);

  Writer wv(seg, seg.find("vrs"));
  std::vector<uint8_t> vrs(32 + 360 * 4);
  auto* v = reinterpret_cast<polyloc_vrs*>(vrs.data());
  v->count = 360;
  v->ranges[359] = 4.25f;
  wv.write(vrs.data(), static_cast<uint32_t>(vrs.size()), 5);
  polyloc_vrs vh{};
  std::vector<float> vr(360);
  uint32_t n = 0;
  EXPECT_EQ(polyloc_read_vrs(c, &vh, vr.data(), 100, &n, nullptr), POLYLOC_ERR_SIZE);
  EXPECT_EQ(n, 360u);
  ASSERT_EQ(polyloc_read_vrs(c, &vh, vr.data(), 360, &n, nullptr), POLYLOC_OK);
  EXPECT_EQ(vr[359], 4.25f);
  Writer wt(seg, seg.find("tracks")), wh(seg, seg.find("health"));
  polyloc_tracks t{};
  t.count = 2;
  t.tracks[1].id = 17;
  wt.write(&t, sizeof t, 6);
  polyloc_health h{};
  h.cycles = 99;
  wh.write(&h, sizeof h, 7);
  polyloc_tracks tout{};
  polyloc_health hout{};
  ASSERT_EQ(polyloc_read_tracks(c, &tout, nullptr), POLYLOC_OK);
  EXPECT_EQ(tout.tracks[1].id, 17u);
  ASSERT_EQ(polyloc_read_health(c, &hout, nullptr), POLYLOC_OK);
  EXPECT_EQ(hout.cycles, 99u);
  std::vector<uint8_t> raw(4096);
  ASSERT_EQ(polyloc_read_newest(c, seg.find("health"), raw.data(), static_cast<uint32_t>(raw.size()), &info), POLYLOC_OK);
  EXPECT_EQ(info.size, sizeof h);
  EXPECT_EQ(polyloc_read_newest(c, seg.find("health"), raw.data(), 10, &info), POLYLOC_ERR_SIZE);
  polyloc_detach(c);
  EXPECT_EQ(seg.ring(scan)->writer_pid, 0);   // detach released the writer roles
}

TEST(ShmCAbi, CommandsForTheBase) {
  test::ShmName name;
  std::vector<shm::ChannelSpec> specs = test::rigChannels();
  specs.push_back(test::spec("cmd_vel", POLYLOC_KIND_COMMAND, POLYLOC_DIR_INPUT, 8));
  auto seg = Segment::create(name, specs);
  seg.ready();
  polyloc_client *ctl = nullptr, *base = nullptr;
  ASSERT_EQ(polyloc_attach(name.str().c_str(), &ctl), POLYLOC_OK);
  ASSERT_EQ(polyloc_attach(name.str().c_str(), &base), POLYLOC_OK);
  const int cmd = polyloc_channel(ctl, "cmd_vel");
  ASSERT_GE(cmd, 0);
  polyloc_command got;
  polyloc_frame_info info;
  EXPECT_EQ(polyloc_read_command(base, &got, &info), POLYLOC_NO_DATA);
  ASSERT_EQ(polyloc_write_command(ctl, cmd, 1000, 0.4, 0.0, -0.25, POLYLOC_NAV_DRIVING, 3, "lab 1: passing door 'lab 1'"),
            POLYLOC_OK) << lastError();
  ASSERT_EQ(polyloc_read_command(base, &got, &info), POLYLOC_OK) << lastError();
  EXPECT_EQ(got.stamp_ns, 1000);
  EXPECT_EQ(info.stamp_ns, 1000);
  EXPECT_DOUBLE_EQ(got.vx, 0.4);
  EXPECT_DOUBLE_EQ(got.wz, -0.25);
  EXPECT_EQ(got.nav_state, uint32_t(POLYLOC_NAV_DRIVING));
  EXPECT_EQ(got.goal, 3u);
  EXPECT_STREQ(got.status, "lab 1: passing door 'lab 1'");
  // A status line longer than the field is cut, NUL-terminated.
  const std::string longer(200, 's');
  ASSERT_EQ(polyloc_write_command(ctl, cmd, 2000, 0, 0, 0, POLYLOC_NAV_REACHED, 3, longer.c_str()), POLYLOC_OK);
  ASSERT_EQ(polyloc_read_command(base, &got, nullptr), POLYLOC_OK);
  EXPECT_EQ(std::string(got.status), std::string(63, 's'));
  ASSERT_EQ(polyloc_write_command(ctl, cmd, 3000, 0, 0, 0, POLYLOC_NAV_IDLE, 0, nullptr), POLYLOC_OK);
  ASSERT_EQ(polyloc_read_command(base, &got, nullptr), POLYLOC_OK);
  EXPECT_STREQ(got.status, "");
  // Out of domain: refused before anything is written, the field named.
  EXPECT_EQ(polyloc_write_command(ctl, cmd, 4000, std::nan(""), 0, 0, 1, 0, ""), POLYLOC_ERR_ARGUMENT);
  EXPECT_NE(lastError().find("vx is nan: not within +-100"), std::string::npos) << lastError();
  EXPECT_EQ(polyloc_write_command(ctl, cmd, 4000, 0, 0, 1e19, 1, 0, ""), POLYLOC_ERR_ARGUMENT);
  EXPECT_NE(lastError().find("wz is 10000000000000000000"), std::string::npos) << lastError();
  EXPECT_EQ(polyloc_write_command(ctl, cmd, 4000, 0, 0, 0, 9, 0, ""), POLYLOC_ERR_ARGUMENT);
  EXPECT_NE(lastError().find("nav_state 9"), std::string::npos) << lastError();
  ASSERT_EQ(polyloc_read_command(base, &got, &info), POLYLOC_OK);
  EXPECT_EQ(got.stamp_ns, 3000) << "a refused command must not be written";
  // Not the command channel.
  EXPECT_EQ(polyloc_write_command(ctl, polyloc_channel(ctl, "odom"), 5000, 0, 0, 0, 1, 0, ""), POLYLOC_ERR_KIND);
  polyloc_detach(ctl);
  polyloc_detach(base);
}

TEST(ShmCAbi, BusyWriterRoleStaleAndReattach) {
  test::ShmName name;
  auto seg = std::make_unique<Segment>(Segment::create(name, test::rigChannels()));
  seg->ready();
  polyloc_client* c = nullptr;
  ASSERT_EQ(polyloc_attach(name.str().c_str(), &c), POLYLOC_OK);
  const int odom = polyloc_channel(c, "odom");
  seg->ring(odom)->writer_pid = getppid();   // a live other process holds it
  const double p7[7] = {0, 0, 0, 1, 0, 0, 0};
  EXPECT_EQ(polyloc_write_odometry(c, odom, 1, p7, nullptr), POLYLOC_ERR_BUSY);
  EXPECT_NE(lastError().find("held by running process"), std::string::npos) << lastError();
  EXPECT_EQ(polyloc_claim_writer(c, odom, 1), POLYLOC_OK);
  EXPECT_EQ(polyloc_write_odometry(c, odom, 1, p7, nullptr), POLYLOC_OK);

  EXPECT_EQ(polyloc_stale(c), 0);
  const uint32_t g = polyloc_generation(c);
  seg->stop();
  EXPECT_EQ(polyloc_stale(c), 1);
  EXPECT_EQ(polyloc_wait(c, polyloc_channel(c, "pose"), 1'000'000), POLYLOC_ERR_STALE);
  seg.reset();
  auto again = Segment::create(name, test::rigChannels());
  again.ready();
  ASSERT_EQ(polyloc_reattach(c), POLYLOC_OK);
  EXPECT_EQ(polyloc_generation(c), g + 1);
  EXPECT_EQ(polyloc_stale(c), 0);
  Writer wp(again, again.find("pose"));
  polyloc_pose q{};
  q.x = 8;
  wp.write(&q, sizeof q, 1);
  polyloc_pose out{};
  ASSERT_EQ(polyloc_next_pose(c, &out, nullptr), POLYLOC_OK);
  EXPECT_EQ(out.x, 8.0);
  EXPECT_EQ(polyloc_write_odometry(c, polyloc_channel(c, "odom"), 2, p7, nullptr), POLYLOC_OK);
  polyloc_detach(c);
  Segment::unlink(name);
  polyloc_client* gone = nullptr;
  EXPECT_EQ(polyloc_attach(name.str().c_str(), &gone), POLYLOC_ERR_NOT_FOUND);
}

// The docs' example controller against a stand-in daemon: it answers the controller's scan
// with a pose, which the controller prints.
TEST(ShmCAbi, ExampleControllerGetsItsPose) {
  test::ShmName name;
  auto seg = Segment::create(name, test::rigChannels());
  seg.ready();
  bool scan_ok = false, odom_ok = false;
  // Attached before the controller starts: a reader made in the thread could come after the
  // controller's scan on a loaded machine, and Start::Next would then never see it.
  Reader scan(seg, seg.find("scan/front")), odom(seg, seg.find("odom"));
  Writer pose(seg, seg.find("pose"));
  std::thread daemon([&] {
    std::vector<uint8_t> p;
    if (!scan.wait(10'000'000'000)) return;
    if (auto f = scan.next(p)) {
      const auto* r = reinterpret_cast<const polyloc_ranges*>(p.data());
      scan_ok = f->size == 16 + 541 * 4 && r->count == 541 && r->ranges[0] == 2.0f;
    }
    odom_ok = odom.newest(p).has_value();
    polyloc_pose q{};
    q.x = 1.25;
    q.y = -0.5;
    q.qw = std::cos(0.15);
    q.qz = std::sin(0.15);
    q.status = POLYLOC_POSE_TRACKING;
    q.ess = 512;
    pose.write(&q, sizeof q, 1);
  });
  const std::string cmd = std::string(POLYLOC_CONTROLLER_EXAMPLE) + " " + name.str() + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pclose(pipe);
  daemon.join();
  EXPECT_EQ(status, 0) << out;
  EXPECT_TRUE(scan_ok);
  EXPECT_TRUE(odom_ok);
  EXPECT_NE(out.find("wrote odometry and a scan of 541 beams on scan/front"), std::string::npos) << out;
  EXPECT_NE(out.find("pose frame 0: x 1.250 y -0.500 yaw 0.300 status 1 ess 512.0"), std::string::npos) << out;
}

}  // namespace
}  // namespace polyloc

// The yaw of a quaternion, as controllers read it off a pose: the kernels' own definition.
TEST(ShmCAbi, QuaternionYawIsThePosesYaw) {
  for (const auto& [r, p, y] : {std::tuple{0.0, 0.0, 0.3}, std::tuple{0.0, 0.0, -3.1}, std::tuple{0.02, -0.03, 1.7},
                                std::tuple{0.0, 0.0, M_PI}}) {
    const polyloc::Pose pose = polyloc::Pose::fromXYZRPY(1, 2, 0, r, p, y);
    const Eigen::Quaterniond& q = pose.rotation();
    EXPECT_EQ(polyloc_quaternion_yaw(q.w(), q.x(), q.y(), q.z()), pose.yaw());
    EXPECT_NEAR(std::remainder(polyloc_quaternion_yaw(q.w(), q.x(), q.y(), q.z()) - y, 2 * M_PI), 0.0, 1e-12);
  }
}
