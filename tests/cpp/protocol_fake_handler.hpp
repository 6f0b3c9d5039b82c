// A ControlHandler with fixed, known answers for the protocol tests and the fuzzer: a pose,
// two raw scanners behind the VRS, a few tracks and inputs. It records what was set, under a
// mutex, since the server calls it from its own thread while the test reads it.
#pragma once

#include "protocol/handler.hpp"

#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

namespace polyloc::protocol::fake {

class FakeHandler : public ControlHandler {
 public:
  // What the fake answers; change under lock() from a test.
  PoseStatus pose_status = PoseStatus::Tracking;
  uint32_t scan_beams = 181;  // beams of every scan (the slow-client test makes them large)
  bool have_scans = true;
  bool throw_on_tracks = false;
  bool collision_avoidance = true;
  std::optional<PoseSeed> last_seed;
  int global_calls = 0;

  std::unique_lock<std::mutex> lock() { return std::unique_lock(mu_); }

  static Pose truePose() { return Pose::fromXYZRPY(1.25, -2.5, 0.0, 0.0, 0.0, 0.5); }

  std::optional<PoseReport> pose() override {
    auto l = lock();
    if (pose_status == PoseStatus::Initialising) return std::nullopt;
    PoseReport p;
    p.stamp_ns = 1'700'000'000'123'456'789;
    p.pose = truePose();
    for (int i = 0; i < 6; ++i) p.covariance(i, i) = 0.01 * (i + 1);
    p.covariance(0, 1) = p.covariance(1, 0) = 0.002;
    p.status = pose_status;
    p.ess = 812.5;
    p.particles = 2000;
    return p;
  }

  Status setPose(const PoseSeed& seed) override {
    auto l = lock();
    if (std::abs(seed.x) > 1000 || std::abs(seed.y) > 1000)
      return Status::BadArgument;  // "outside the map"
    last_seed = seed;
    pose_status = PoseStatus::Uncertain;
    return Status::Ok;
  }

  Status globalLocalization() override {
    auto l = lock();
    ++global_calls;
    pose_status = PoseStatus::Initialising;
    return Status::Ok;
  }

  std::vector<ScannerInfo> scanners() override {
    auto l = lock();
    return {{"vrs", Pose(), scan_beams},
            {"front", Pose::fromXYZRPY(0.3, 0.0, 0.25, 0, 0, 0), scan_beams},
            {"rear", Pose::fromXYZRPY(-0.3, 0.0, 0.25, 0, 0, 3.14159265358979323846), scan_beams}};
  }

  std::optional<PolarScan> scan(uint32_t index) override {
    auto l = lock();
    if (!have_scans) return std::nullopt;
    PolarScan s;
    s.stamp_ns = 1'700'000'000'000'000'000 + index;
    for (uint32_t i = 0; i < scan_beams; ++i) {
      s.angles.push_back(float(-M_PI / 2 + M_PI * i / std::max(1u, scan_beams - 1)));
      // index + 1 metres, every 10th beam without a return (sent as +inf whatever it was)
      s.ranges.push_back(i % 10 == 9 ? std::numeric_limits<float>::quiet_NaN() : float(index + 1) + 0.001f * i);
    }
    return s;
  }

  bool collisionAvoidance() override {
    auto l = lock();
    return collision_avoidance;
  }
  void setCollisionAvoidance(bool on) override {
    auto l = lock();
    collision_avoidance = on;
  }

  TrackList tracks() override {
    auto l = lock();
    if (throw_on_tracks) throw std::runtime_error("tracker not running");
    TrackList t;
    t.stamp_ns = 42;
    t.tracks.push_back({7, true, 3.0, 1.0, 0.5, -0.25, {0.04, 0.001, 0.001, 0.05}});
    t.tracks.push_back({9, false, -1.0, 2.0, 0.0, 0.0, {0.2, 0.0, 0.0, 0.2}});
    return t;
  }

  HealthReport health() override {
    auto l = lock();
    HealthReport h;
    h.stamp_ns = 1'700'000'000'000'000'000;
    h.uptime_s = 12.5;
    h.pose_status = pose_status;
    h.cycles = 1000, h.poses = 990, h.vrs = 1000, h.tracks = 995;
    h.pose_rate_hz = 12.5;
    h.cycle_p50_ms = 3.25, h.cycle_p99_ms = 9.5;
    h.inputs.push_back({"scan/front", 12.5, 5000, 3, 0.02, false});
    h.inputs.push_back({"odom", 0.0, 100, 0, 4.5, true});
    return h;
  }

 private:
  std::mutex mu_;
};

}  // namespace polyloc::protocol::fake
