#include <polyloc/eval/real_log_runs.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/io/restamp.hpp>
#include <polyloc/sim/simulator.hpp>  // toMsgPose

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace polyloc {
namespace {

constexpr uint64_t kDriftStream = 0x445246ULL << 40;

// Positive and increasing (strictly, or allowing repeats: odometry may come twice a stamp).
bool increasing(const std::vector<int64_t>& t, bool strict = true) {
  for (size_t i = 1; i < t.size(); ++i)
    if (t[i] < t[i - 1] || (strict && t[i] == t[i - 1])) return false;
  return !t.empty() && t.front() > 0;
}

msg::Odometry odometryMsg(int64_t t, const Pose& p) {
  msg::Odometry o;
  o.header = {msg::fromNs(t), "odom"};
  o.child_frame_id = "base_link";
  o.pose.pose = toMsgPose(p);
  return o;
}

msg::PoseStamped poseMsg(int64_t t, const Pose& p) {
  msg::PoseStamped m;
  m.header = {msg::fromNs(t), "map"};
  m.pose = toMsgPose(p);
  return m;
}

// The scan as the run carries it: its stamp replaced by the run's.
RecordedMessage scanMessage(const RealLog& log, const LoggedScan& s, int64_t t) {
  msg::LaserScan scan = s.scan;
  scan.header.stamp = msg::fromNs(t);
  return RecordedMessage{log.topic, t, t, std::move(scan)};
}

// Odometry alone: the first truth pose moved by the odometry between the first scan and each.
std::vector<StampedPose> chainOdometry(const std::vector<StampedPose>& odom, const std::vector<StampedPose>& truth) {
  std::vector<StampedPose> out;
  if (truth.empty() || odom.empty()) return out;
  const Pose start = truth.front().pose, o0 = odometryAt(odom, truth.front().stamp_ns);
  for (const auto& t : truth) out.push_back({t.stamp_ns, start * (o0.inverse() * odometryAt(odom, t.stamp_ns))});
  return out;
}

}  // namespace

Pose odometryAt(const std::vector<StampedPose>& odom, int64_t t) {
  if (odom.empty()) return Pose();
  if (t <= odom.front().stamp_ns) return odom.front().pose;
  if (t >= odom.back().stamp_ns) return odom.back().pose;
  auto hi = std::lower_bound(odom.begin(), odom.end(), t, [](const StampedPose& p, int64_t v) { return p.stamp_ns < v; });
  auto lo = hi - 1;
  if (hi->stamp_ns == lo->stamp_ns) return hi->pose;
  return Pose::interpolate(lo->pose, hi->pose, double(t - lo->stamp_ns) / double(hi->stamp_ns - lo->stamp_ns));
}

RealLogSplit splitEvenOdd(const RealLog& log, size_t every) {
  RealLogSplit s;
  every = std::max<size_t>(every, 2);
  for (size_t i = 0; i < log.scans.size(); ++i) {
    if (i % 2 == 0) s.map_scans.push_back(i);
    else if ((i / 2) % (every / 2) == 0) s.test_scans.push_back(i);
  }
  return s;
}

TestRun driftRun(const RealLog& log, const std::vector<size_t>& test, const OdometryDrift& d, double restamp_hz) {
  TestRun run;
  run.name = "drift";
  std::vector<int64_t> stamps;
  for (size_t i : test) stamps.push_back(log.scans[i].stamp_ns);
  if (!increasing(stamps)) {
    run.stamps = fmt::format("restamped by order at {:g} Hz: the test scans' stamps do not increase", restamp_hz);
    for (size_t k = 0; k < test.size(); ++k) stamps[k] = restampedNs(log.scans[test[k]].order, restamp_hz);
  }
  const CounterRng rng(d.seed);
  Pose odom = Pose::planar(0, 0, 0);
  std::vector<StampedPose> odom_path;
  for (size_t k = 0; k < test.size(); ++k) {
    const LoggedScan& s = log.scans[test[k]];
    if (k > 0) {
      // The true step in the previous pose's frame, then noise scaled by its length and turn.
      const Pose step = log.scans[test[k - 1]].pose.planarProjection().inverse() * s.pose.planarProjection();
      const double dist = std::hypot(step.x(), step.y()), turn = std::abs(step.yaw());
      const double st = d.translation * dist, sr = d.rotation * turn + d.rotation_per_m * dist;
      const Pose noisy = Pose::planar(step.x() + st * rng.normal(kDriftStream, k, 0), step.y() + st * rng.normal(kDriftStream, k, 1),
                                      step.yaw() + sr * rng.normal(kDriftStream, k, 2));
      odom = odom * noisy;
    }
    odom_path.push_back({stamps[k], odom});
    run.messages.push_back(RecordedMessage{"/odom", stamps[k], stamps[k], odometryMsg(stamps[k], odom)});
    run.messages.push_back(scanMessage(log, s, stamps[k]));
    run.messages.push_back(RecordedMessage{"/ground_truth", stamps[k], stamps[k], poseMsg(stamps[k], s.pose)});
    run.truth.push_back({stamps[k], s.pose});
  }
  run.odometry = odom_path.size();
  run.odometry_only = chainOdometry(odom_path, run.truth);
  return run;
}

TestRun ownOdometryRun(const RealLog& log, const std::vector<size_t>& test, double restamp_hz) {
  TestRun run;
  run.name = "own";
  if (test.empty()) return run;
  const uint64_t first = log.scans[test.front()].order, last = log.scans[test.back()].order;
  // The log's odometry over the test span (from the last message before the first test scan:
  // the filter starts at the first message it reads), without the copies of logged scan poses.
  std::vector<const LoggedOdometry*> odom;
  size_t si = 0;  // the last scan (of any parity) before each odometry message
  for (const auto& o : log.odometry) {
    while (si + 1 < log.scans.size() && log.scans[si + 1].order < o.order) ++si;
    const LoggedScan& s = log.scans[si];
    const bool copy = s.order < o.order && (s.pose.translation() - o.pose.translation()).norm() < 1e-6 &&
                      std::abs(angleDiff(s.pose.yaw(), o.pose.yaw())) < 1e-6;
    if (copy) {
      ++run.odometry_dropped;
      continue;
    }
    if (o.order < first) odom.assign(1, &o);
    else if (o.order <= last) odom.push_back(&o);
  }
  // Recorded stamps when scans and odometry each increase; else all by order.
  std::vector<int64_t> scan_t, odom_t;
  for (size_t i : test) scan_t.push_back(log.scans[i].stamp_ns);
  for (const auto* o : odom) odom_t.push_back(o->stamp_ns);
  const bool recorded = increasing(scan_t) && (odom_t.empty() || increasing(odom_t, false));
  if (!recorded)
    run.stamps = fmt::format("restamped by order at {:g} Hz: the {} stamps do not increase", restamp_hz,
                             increasing(scan_t) ? "odometry" : "scans'");
  auto stamp = [&](int64_t t, uint64_t order) { return recorded ? t : restampedNs(order, restamp_hz); };
  std::vector<StampedPose> odom_path;
  size_t oi = 0;
  for (size_t i : test) {
    const LoggedScan& s = log.scans[i];
    for (; oi < odom.size() && odom[oi]->order < s.order; ++oi) {
      const int64_t t = stamp(odom[oi]->stamp_ns, odom[oi]->order);
      odom_path.push_back({t, odom[oi]->pose});
      run.messages.push_back(RecordedMessage{"/odom", t, t, odometryMsg(t, odom[oi]->pose)});
    }
    const int64_t t = stamp(s.stamp_ns, s.order);
    run.messages.push_back(scanMessage(log, s, t));
    run.messages.push_back(RecordedMessage{"/ground_truth", t, t, poseMsg(t, s.pose)});
    run.truth.push_back({t, s.pose});
  }
  run.odometry = odom_path.size();
  run.odometry_only = chainOdometry(odom_path, run.truth);
  if (run.odometry < test.size())
    run.unusable = fmt::format("{} ODOM lines are copies of the logged scan poses (the corrector's), {} left for {} test scans: "
                               "the log has no odometry of its own",
                               run.odometry_dropped, run.odometry, test.size());
  return run;
}

}  // namespace polyloc
