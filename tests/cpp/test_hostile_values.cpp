// The property of docs/failure.md, swept: every value of {0, -0, tiny, 1e19, 1e300, -1e300, inf,
// nan} in every numeric field of polylocd's inputs (odometry and scan frames on shared memory,
// SETPOSE's x, y, yaw and spreads, a recording's odometry and scans) against a running daemon
// and the recording job: the daemon lives, each value is
// taken or refused exactly as its domain says, refusals are counted with their reason, and the
// pose published before survives.
#include "pipeline/control.hpp"
#include "reloc/recording_job.hpp"
#include "reloc/report.hpp"
#include "sim_fixtures.hpp"
#include "pipeline/daemon.hpp"
#include "pipeline/shm_payloads.hpp"
#include "shm/channel.hpp"
#include "shm_fixtures.hpp"

#include <polyloc/geometry/domain.hpp>
#include <polyloc/io/memory_recording.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/sim/scenario.hpp>
#include <polyloc/sim/simulator.hpp>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_hostile_values {

using namespace polyloc;
using namespace polyloc::pipeline;
using namespace std::chrono_literals;


constexpr double kInf = std::numeric_limits<double>::infinity();
const double kValues[] = {0.0, -0.0, 1e-300, 1e19, 1e300, -1e300, kInf, std::numeric_limits<double>::quiet_NaN()};

int64_t realtimeNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::optional<polyloc_health> health(const shm::Segment& seg) { return test::readHealth(seg); }

uint64_t seen(const polyloc_input_health& x) {
  return x.taken + x.rejected_nan + x.rejected_size + x.rejected_stale + x.rejected_future + x.overruns;
}

struct HostileValues : ::testing::Test {
  std::string instance = fmt::format("test_hostile_{}", getpid());
  std::unique_ptr<Daemon> daemon;
  std::atomic<bool> stop{false};
  std::thread thread;
  void SetUp() override {
    ServiceConfig c = loadServiceConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
    c.daemon.instance = instance;
    c.daemon.threads = 2;
    c.daemon.control.enabled = false;
    c.daemon.live.port = 0;  // a viewer the developer runs keeps its port
    c.daemon.init = InitPose{Pose::planar(1.3, 1.75, 0)};
    daemon = std::make_unique<Daemon>(std::move(c));
    thread = std::thread([this] { daemon->run(stop); });
  }
  void TearDown() override {
    stop = true;
    thread.join();
    shm::Segment::unlink(instance);
  }
  shm::Segment attach() {
    for (int i = 0;; ++i) try {
        return shm::Segment::attach(instance);
      } catch (const shm::ShmError&) {
        if (i > 200) throw;
        std::this_thread::sleep_for(20ms);
      }
  }
  // Waits until `input` has seen `frames` frames in all (30 s at most).
  polyloc_input_health settle(const shm::Segment& seg, int input, uint64_t frames) {
    const auto end = std::chrono::steady_clock::now() + 30s;
    polyloc_input_health x{};
    while (std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(50ms);
      if (auto h = health(seg)) x = h->input[input];
      if (seen(x) >= frames) break;
    }
    return x;
  }
};


TEST_F(HostileValues, EveryValueInEveryShmFieldIsTakenOrRefusedByItsDomain) {
  shm::Segment seg = attach();
  const int odom = seg.find("odom"), scan = seg.find("scan/s300_front_left");
  ASSERT_GE(odom, 0);
  ASSERT_GE(scan, 0);
  shm::Writer wo(seg, odom), ws(seg, scan);
  int64_t t = realtimeNs();
  uint64_t odom_sent = 0, odom_ok = 0;
  for (int field = 0; field < 7; ++field)
    for (double v : kValues) {
      polyloc_odometry o = odometryPayload(t += 1'000'000, Pose::planar(1, 2, 0.3));
      double* f[7] = {&o.x, &o.y, &o.z, &o.qw, &o.qx, &o.qy, &o.qz};
      *f[field] = v;
      const double norm = std::sqrt(o.qw * o.qw + o.qx * o.qx + o.qy * o.qy + o.qz * o.qz);
      bool ok = std::isfinite(norm) && std::fabs(norm - 1) <= 1e-3;
      for (int k = 0; k < 3; ++k) ok = ok && std::isfinite(*f[k]) && std::fabs(*f[k]) <= domain::kMaxCoordinate;
      wo.write(&o, sizeof o, o.stamp_ns);
      ++odom_sent, odom_ok += ok;
    }
  const uint32_t beams = seg.channel(scan).count;
  uint64_t scans_ok = 0;
  for (double v : kValues) {
    std::vector<uint8_t> frame(offsetof(polyloc_ranges, ranges) + 4 * beams);
    const polyloc_ranges rh{t += 1'000'000, beams, 0};
    std::memcpy(frame.data(), &rh, sizeof rh);
    const float r = float(v);
    for (uint32_t i = 0; i < beams; ++i) std::memcpy(frame.data() + offsetof(polyloc_ranges, ranges) + 4 * i, &r, 4);
    ws.write(frame.data(), uint32_t(frame.size()), rh.stamp_ns);
    scans_ok += std::isfinite(r) && r >= 0 && r <= domain::kMaxRange;
  }
  const polyloc_input_health ho = settle(seg, odom, odom_sent), hs = settle(seg, scan, std::size(kValues));
  EXPECT_EQ(ho.taken, odom_ok);
  EXPECT_EQ(ho.rejected_nan, odom_sent - odom_ok);  // 1e19 as well as NaN
  EXPECT_EQ(hs.taken, scans_ok);
  EXPECT_EQ(hs.rejected_nan, std::size(kValues) - scans_ok);
  EXPECT_EQ(odom_ok, 5u * 3u);  // 0, -0 and tiny in x, y, z, and in qx, qy (zero already: the norm stays 1)
  EXPECT_EQ(scans_ok, 3u);
  // Alive: it still publishes health.
  const uint64_t cycles = health(seg)->cycles;
  const auto end = std::chrono::steady_clock::now() + 10s;
  while (health(seg)->stamp_ns <= realtimeNs() - 2'000'000'000 && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(50ms);
  EXPECT_GE(health(seg)->cycles, cycles);
}

TEST_F(HostileValues, EveryValueInEverySetposeFieldIsBadArgumentOutsideItsDomain) {
  DaemonControl control(daemon->live(), daemon->config(), {}, daemon->mapBounds());
  const Eigen::AlignedBox3f map = daemon->mapBounds();
  size_t refused = 0, accepted = 0;
  for (int field = 0; field < 5; ++field)
    for (double v : kValues) {
      protocol::PoseSeed s{1.3, 1.75, 0.0, 0.1, 0.1};
      double* f[5] = {&s.x, &s.y, &s.yaw, &*s.sigma_xy_m, &*s.sigma_yaw_rad};
      *f[field] = double(float(v));  // as the wire carries it
      const double x = *f[field];
      bool ok = std::isfinite(x);
      if (field == 0) ok = ok && x >= map.min().x() - domain::kMapMargin && x <= map.max().x() + domain::kMapMargin;
      if (field == 1) ok = ok && x >= map.min().y() - domain::kMapMargin && x <= map.max().y() + domain::kMapMargin;
      if (field == 2) ok = ok && std::fabs(x) <= domain::kMaxAngle;
      if (field == 3) ok = ok && x >= 0 && x <= domain::kMaxPositionSigma;
      if (field == 4) ok = ok && x >= 0 && x <= domain::kMaxAngle;
      const protocol::Status st = control.setPose(s);
      EXPECT_EQ(st, ok ? protocol::Status::Ok : protocol::Status::BadArgument) << "field " << field << " value " << v;
      (ok ? accepted : refused) += 1;
    }
  EXPECT_EQ(refused, 5u * 5u);  // 1e19, +-1e300, inf, nan in each field (1e19 m is off the map, 1e19 rad beyond 100)
  EXPECT_EQ(accepted, 5u * 3u);
}

// The same values in a recording's fields (odometry position, every range of a scan) through
// the recording job localize and relocalize use: a value outside its domain is ignored and
// counted (odometry_invalid; beams outside the sensor's range are no returns), the run goes on
// and its accuracy holds.
TEST(HostileRecording, EveryValueInTheOdometryAndScansLeavesTheRunOnTrack) {
  const test::LabTour tour(3);
  const auto& rec = tour.rec;
  const PolylocConfig cfg = loadConfig(std::string(POLYLOC_SOURCE_DIR) + "/maps/config/lab.yaml");
  const Mesh mesh = loadMesh(cfg.map.file, cfg.map.load);
  EmbreeCaster caster(mesh);
  for (double v : kValues) {
    auto msgs = std::make_shared<std::vector<RecordedMessage>>();
    size_t odom_seen = 0, scans_seen = 0, scans_changed = 0;
    for (const auto& e : rec.entries) {
      RecordedMessage m{e.topic, e.stamp, e.stamp, e.message};
      if (auto* o = std::get_if<msg::Odometry>(&m.message); o && ++odom_seen == 40) o->pose.pose.position.x = v;
      if (auto* l = std::get_if<msg::LaserScan>(&m.message); l && ++scans_seen % 25 == 0)
        std::fill(l->ranges.begin(), l->ranges.end(), float(v)), ++scans_changed;
      msgs->push_back(std::move(m));
    }
    reloc::JobOptions jo;
    jo.input = fmt::format("lab tour with {}", v);
    jo.open = [msgs] { return readMemory(msgs); };
    const reloc::JobResult r = reloc::runRecordingJob({cfg, mesh, caster, nullptr}, jo);
    const bool odom_ok = std::isfinite(v) && std::fabs(v) <= domain::kMaxCoordinate;
    EXPECT_EQ(r.counters.at("odometry_invalid"), odom_ok ? 0u : 1u) << v;
    // None of the values is a distance a scanner measures (1e-300 is 0 as a float): every
    // changed scan is refused, with its reason.
    EXPECT_EQ(r.counters.at("scans_no_valid_range"), scans_changed) << v;
    EXPECT_GT(scans_changed, 5u);
    const auto m = reloc::evaluate(r);
    ASSERT_TRUE(m) << v;
    EXPECT_LT(m->all.p95_pos_err_m, 0.05) << v;
    EXPECT_EQ(r.final_status, MclStatus::Tracking) << v;
  }
}

}  // namespace polyloc::t_hostile_values
