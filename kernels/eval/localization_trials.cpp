#include <polyloc/eval/ground_truth.hpp>
#include <polyloc/eval/localization_trials.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/mcl/free_floor.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/sim/simulator.hpp>
#include <algorithm>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {

constexpr uint64_t kStartStream = 0x545253ULL << 40;  // "TRS": start poses
constexpr uint64_t kRouteStream = 0x545252ULL << 40;  // "TRR": route turns

// Everything the robot produced on one drive, in time order: odometry ticks and sensor frames.
struct Event {
  int64_t stamp = 0;
  int sensor = -1;           // -1: an odometry tick
  Pose odom, truth;          // tick: odom_T_base and map_T_base
  std::vector<float> ranges;  // frame
};

struct Drive {
  Pose start;
  std::vector<Event> events;
  std::vector<StampedPose> truth;
};

// Free distance ahead at the robot's heights, along three parallel lines (centre and both
// flanks), so the body fits through.
double freeAhead(const RayCaster& caster, const Eigen::Vector2d& p, double yaw, double half_width) {
  const Eigen::Vector2d d(std::cos(yaw), std::sin(yaw)), n(-d.y(), d.x());
  std::vector<float> ox, oy, oz, dx, dy, dz;
  for (double side : {-half_width, 0.0, half_width})
    for (double h : {0.1, 0.5, 0.9}) {
      const Eigen::Vector2d o = p + side * n;
      ox.push_back(float(o.x())), oy.push_back(float(o.y())), oz.push_back(float(h));
      dx.push_back(float(d.x())), dy.push_back(float(d.y())), dz.push_back(0.f);
    }
  std::vector<float> r(ox.size());
  RayBatch rays{ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), nullptr, nullptr, ox.size()};
  HitBuffers out;
  out.range = r.data();
  caster.castRays(rays, out);
  double free = 1e9;
  for (float v : r) free = std::min(free, std::isfinite(v) ? double(v) : 1e9);
  return free;
}

// A random drive from a free start: straight legs as far as the body fits (at most 2.5 m),
// turning by a random angle where it does not.
RouteSpec randomRoute(const RayCaster& caster, Pose& start, double length, double half_width,
                      const CounterRng& rng, uint64_t stream) {
  RouteSpec route;
  route.start_pause = 0.0;
  Eigen::Vector2d p(start.x(), start.y());
  double yaw = start.yaw(), travelled = 0;
  route.waypoints.push_back(Waypoint{p, std::nullopt, 0.0, true});
  bool first = true;
  for (uint64_t k = 0; k < 40 && travelled < length; ++k) {
    const double ahead = freeAhead(caster, p, yaw, half_width) - half_width - 0.3;
    if (ahead < 0.6) {
      yaw += rng.uniform(0.5 * M_PI, 1.5 * M_PI, stream, k);
      continue;
    }
    if (first) start = Pose::fromXYZRPY(start.x(), start.y(), start.z(), start.roll(), start.pitch(), yaw), first = false;
    const double step = std::min({ahead, 2.5, length - travelled});
    p += step * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
    route.waypoints.push_back(Waypoint{p, std::nullopt, 0.0, true});
    travelled += step;
    yaw += rng.uniform(-0.5 * M_PI, 0.5 * M_PI, stream, 1000 + k);
  }
  return route;
}

Drive simulateDrive(Scenario s, const Mesh& map, const RouteSpec& route, const Pose& start) {
  s.route = route;
  s.duration = 0;
  s.chairs = {};  // the routes are checked against the map as it is
  Simulator sim(std::move(s), map);
  Drive d;
  d.start = start;
  NullRecordingWriter null;
  SimHooks hooks;
  hooks.on_tick = [&](int64_t t, const Pose& gt, const Pose& odom) {
    d.events.push_back(Event{t, -1, odom, gt, {}});
    d.truth.push_back({t, gt});
  };
  hooks.on_frame = [&](const SimFrame& f) {
    d.events.push_back(Event{f.stamp_ns, int(f.sensor), {}, f.map_T_base, f.measured});
  };
  sim.run(null, hooks);
  // Ticks of a simulated second come before its frames: put them in time order (stable: a tick
  // before a frame of the same stamp).
  std::stable_sort(d.events.begin(), d.events.end(), [](const Event& a, const Event& b) {
    return a.stamp != b.stamp ? a.stamp < b.stamp : (a.sensor < 0) > (b.sensor < 0);
  });
  return d;
}

// Feeds events [from, end) to the filter; odometry as `odom_offset * odom`, stamps shifted by
// `dt`. Calls on_round(estimate) after every round; stops when it returns false.
template <class F>
size_t feed(Localizer& loc, const Drive& d, size_t from, const Pose& odom_offset, int64_t dt, double& filter_s,
            F&& on_round) {
  using Clock = std::chrono::steady_clock;
  size_t i = from;
  for (; i < d.events.size(); ++i) {
    const Event& e = d.events[i];
    const auto t0 = Clock::now();
    bool closed = false;
    if (e.sensor < 0) loc.addOdometry(e.stamp + dt, odom_offset * e.odom);
    else closed = loc.addScan(size_t(e.sensor), e.stamp + dt, e.ranges);
    filter_s += std::chrono::duration<double>(Clock::now() - t0).count();
    if (closed && !on_round(loc.estimate())) return i + 1;
  }
  return i;
}

// The error of a round's estimate against the drive's ground truth (its stamps shifted by dt).
// False once the trial has its rounds.
bool recordRound(TrialResult& r, const GroundTruth& gt, const MclEstimate& e, int64_t dt, const TrialOptions& o) {
  const auto t = gt.at(e.stamp_ns - dt);
  if (!t) return true;
  r.pos_err.push_back((e.pose.translation() - t->translation()).head<2>().norm());
  r.yaw_err.push_back(std::abs(angleDiff(e.pose.yaw(), t->yaw())));
  return r.pos_err.size() < o.rounds + o.hold_rounds;
}

struct TrialSetup {
  EmbreeCaster caster;
  std::unique_ptr<RayCaster> weigh;  // mcl.caster when not embree
  FreeFloor floor;
  double half_width = 0.3;
  TrialSetup(const Mesh& map, const MclConfig& mcl, const Scenario& s)
      : caster(map), weigh(makeWeighingCaster(map, s.config.rig, mcl, mcl.threads)), floor(caster, map, mcl) {
    const RobotSpec& robot = s.config.robot;
    if (robot.footprint.empty()) half_width = robot.radius;
    for (const auto& v : robot.footprint) half_width = std::max(half_width, std::abs(v.y()));
  }
  Drive drive(const Scenario& s, const Mesh& map, const TrialOptions& o, uint64_t index) {
    const CounterRng rng(o.seed);
    for (uint64_t attempt = 0; attempt < 20; ++attempt) {
      const uint64_t key = index * 64 + attempt;
      const std::vector<Pose> p = floor.sampleFree(1, rng, kStartStream + key);
      if (p.empty()) throw std::runtime_error("no free floor for the robot in the map");
      Pose start = p[0];
      RouteSpec r = randomRoute(caster, start, o.route_length, half_width, rng, kRouteStream + key);
      if (r.waypoints.size() < 2) continue;  // boxed in: another start
      Scenario si = s;
      si.route.waypoints = {};
      r.max_speed = s.route.max_speed, r.max_acceleration = s.route.max_acceleration;
      r.max_yaw_rate = s.route.max_yaw_rate;
      return simulateDrive(si, map, r, start);
    }
    throw std::runtime_error("found no drivable start in 20 attempts");
  }
};

}  // namespace

int convergedRound(const std::vector<double>& pos, const std::vector<double>& yaw, double pos_tol, double yaw_tol) {
  int r = -1;
  for (size_t i = pos.size(); i-- > 0;) {
    if (!(pos[i] < pos_tol && yaw[i] < yaw_tol)) break;
    r = int(i) + 1;
  }
  return r;
}

std::vector<TrialResult> runGlobalTrials(const Scenario& s, const Mesh& map, const MclConfig& mcl,
                                         const TrialOptions& o, const TrialProgress& progress) {
  TrialSetup setup(map, mcl, s);
  std::vector<TrialResult> out;
  for (size_t k = 0; k < o.trials; ++k) {
    const Drive d = setup.drive(s, map, o, k);
    const GroundTruth gt(d.truth);
    TrialResult r;
    r.index = k, r.start = d.start;
    Localizer loc(setup.caster, map, s.config.rig, mcl, setup.weigh.get());
    loc.initGlobal(d.events.front().stamp);
    feed(loc, d, 0, Pose(), 0, r.filter_s, [&](const MclEstimate& e) { return recordRound(r, gt, e, 0, o); });
    r.updates = loc.counters().updates;
    r.injected = loc.counters().injected;
    r.converged_round = convergedRound(r.pos_err, r.yaw_err, o.pos_tol, o.yaw_tol);
    r.converged = r.converged_round > 0 && size_t(r.converged_round) <= o.rounds &&
                  r.pos_err.size() >= o.rounds + o.hold_rounds;
    out.push_back(std::move(r));
    if (progress) progress(k + 1, o.trials);
  }
  return out;
}

std::vector<TrialResult> runKidnapTrials(const Scenario& s, const Mesh& map, const MclConfig& mcl,
                                         const TrialOptions& o, const TrialProgress& progress) {
  TrialSetup setup(map, mcl, s);
  std::vector<TrialResult> out;
  for (size_t k = 0; k < o.trials; ++k) {
    // Drive A is tracked from its true start; after kidnap_after rounds the robot is carried to
    // the start of drive B. Odometry goes on from where A left it, stamps go on from A's.
    const Drive a = setup.drive(s, map, o, 2 * k);
    const Drive b = setup.drive(s, map, o, 2 * k + 1);
    TrialResult r;
    r.index = k, r.start = b.start;
    Localizer loc(setup.caster, map, s.config.rig, mcl, setup.weigh.get());
    Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
    cov.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 1e-4, 1e-4, 1e-4, 0.03 * 0.03;
    loc.initPose(a.start, cov, a.events.front().stamp);
    size_t rounds_a = 0;
    const size_t stop = feed(loc, a, 0, Pose(), 0, r.filter_s, [&](const MclEstimate&) { return ++rounds_a < o.kidnap_after; });
    int64_t t_a = a.events[stop - 1].stamp;
    Pose odom_a;
    for (size_t i = stop; i-- > 0;)
      if (a.events[i].sensor < 0) {
        odom_a = a.events[i].odom;
        break;
      }
    const Pose odom_b0 = b.events.front().sensor < 0 ? b.events.front().odom : Pose();
    const Pose offset = odom_a * odom_b0.inverse();
    const int64_t dt = t_a + 20'000'000 - b.events.front().stamp;
    const GroundTruth gt(b.truth);
    feed(loc, b, 0, offset, dt, r.filter_s, [&](const MclEstimate& e) { return recordRound(r, gt, e, dt, o); });
    r.updates = loc.counters().updates;
    r.injected = loc.counters().injected;
    r.converged_round = convergedRound(r.pos_err, r.yaw_err, o.pos_tol, o.yaw_tol);
    r.converged = rounds_a >= o.kidnap_after && r.converged_round > 0 && size_t(r.converged_round) <= o.rounds &&
                  r.pos_err.size() >= o.rounds + o.hold_rounds;
    out.push_back(std::move(r));
    if (progress) progress(k + 1, o.trials);
  }
  return out;
}

}  // namespace polyloc
