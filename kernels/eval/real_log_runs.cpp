#include <polyloc/eval/real_log_runs.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/io/restamp.hpp>
#include <polyloc/sim/simulator.hpp>  // toMsgPose

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {
namespace {

constexpr uint64_t kDriftStream = 0x445246ULL << 40;
constexpr uint64_t kSlipStream = 0x534C50ULL << 40;

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

OdometryDrift parseDrift(const std::string& spec) {
  const auto bad = [&] {
    return std::invalid_argument(fmt::format("drift '{}': expected low, mid, high, slip or P/D (percent, deg per m), "
                                             "optionally followed by +slip", spec));
  };
  std::string base = spec;
  bool slips = false;
  if (base.ends_with("+slip")) base.resize(base.size() - 5), slips = true;
  OdometryDrift d;
  d.name = spec;
  double pct = 0, deg = 0;
  if (base == "low") pct = 2, deg = 0.5;
  else if (base == "mid") pct = 5, deg = 1;
  else if (base == "high") pct = 10, deg = 2;
  else if (base == "slip") pct = 5, deg = 1, slips = true;
  else {
    const size_t slash = base.find('/');
    if (slash == std::string::npos) throw bad();
    try {
      size_t n1 = 0, n2 = 0;
      pct = std::stod(base.substr(0, slash), &n1);
      deg = std::stod(base.substr(slash + 1), &n2);
      if (n1 != slash || n2 != base.size() - slash - 1) throw bad();
    } catch (const std::logic_error&) {
      throw bad();
    }
    if (!(pct >= 0 && pct <= 100 && deg >= 0 && deg <= 90)) throw bad();
  }
  d.translation = d.rotation = pct / 100;
  d.rotation_per_m = deg * M_PI / 180;
  if (slips) d.slip_every_m = 10;
  return d;
}

std::string describeDrift(const OdometryDrift& d) {
  return fmt::format("{}: {:g} %/{:g} deg per m{}", d.name, 100 * d.translation, d.rotation_per_m * 180 / M_PI,
                     d.slip_every_m > 0 ? fmt::format(", a slip every {:g} m", d.slip_every_m) : "");
}

std::vector<size_t> decimateScans(const std::vector<size_t>& scans, size_t decimate, size_t count) {
  std::vector<size_t> out;
  decimate = std::max<size_t>(decimate, 1);
  for (size_t k = 0; k < scans.size() && k < count; k += decimate) out.push_back(scans[k]);
  return out;
}

std::vector<Pose> driftOdometry(const RealLog& log, const OdometryDrift& d) {
  const CounterRng rng(d.seed);
  std::vector<Pose> out;
  Pose odom = Pose::planar(0, 0, 0);
  for (size_t i = 0; i < log.scans.size(); ++i) {
    if (i > 0) {
      // The true step in the previous pose's frame as rotate-translate-rotate (a step backwards
      // as a backward translation), each part with its noise.
      const Pose step = log.scans[i - 1].pose.planarProjection().inverse() * log.scans[i].pose.planarProjection();
      double trans = std::hypot(step.x(), step.y());
      double rot1 = trans > 1e-4 ? std::atan2(step.y(), step.x()) : 0.0;
      if (std::abs(rot1) > M_PI / 2) rot1 = angleDiff(rot1, M_PI), trans = -trans;
      double rot2 = angleDiff(step.yaw(), rot1);
      const double len = std::abs(trans), per_rot = d.rotation_per_m * len / std::sqrt(2.0);
      trans += d.translation * len * rng.normal(kDriftStream, i, 0);
      rot1 += (d.rotation * std::abs(rot1) + per_rot) * rng.normal(kDriftStream, i, 1);
      rot2 += (d.rotation * std::abs(rot2) + per_rot) * rng.normal(kDriftStream, i, 2);
      Pose noisy = Pose::planar(0, 0, rot1) * Pose::planar(trans, 0, 0) * Pose::planar(0, 0, rot2);
      if (d.slip_every_m > 0 && rng.uniform(kSlipStream, i, 0) < len / d.slip_every_m) {
        const double dir = rng.uniform(-M_PI, M_PI, kSlipStream, i, 1);
        const double m = rng.uniform(d.slip_min_m, d.slip_max_m, kSlipStream, i, 2);
        const double turn = rng.uniform(d.slip_min_rad, d.slip_max_rad, kSlipStream, i, 3) *
                            (rng.uniform(kSlipStream, i, 4) < 0.5 ? -1 : 1);
        noisy = noisy * Pose::planar(m * std::cos(dir), m * std::sin(dir), turn);
      }
      odom = odom * noisy;
    }
    out.push_back(odom);
  }
  return out;
}

TestRun driftRun(const RealLog& log, const std::vector<size_t>& test, const OdometryDrift& d, double restamp_hz) {
  TestRun run;
  run.name = "drift";
  if (test.empty()) return run;
  // Every log scan from the first test scan to the last carries an odometry message: their
  // stamps as recorded when they increase, else all by order.
  std::vector<int64_t> stamps;
  for (size_t i = test.front(); i <= test.back(); ++i) stamps.push_back(log.scans[i].stamp_ns);
  const bool recorded = increasing(stamps);
  if (!recorded)
    run.stamps = fmt::format("restamped by order at {:g} Hz: the scans' stamps do not increase", restamp_hz);
  const auto stampOf = [&](size_t i) { return recorded ? log.scans[i].stamp_ns : restampedNs(log.scans[i].order, restamp_hz); };
  const std::vector<Pose> odom = driftOdometry(log, d);
  std::vector<StampedPose> odom_path;
  size_t next = 0;  // the next test scan
  for (size_t i = test.front(); i <= test.back(); ++i) {
    const int64_t t = stampOf(i);
    odom_path.push_back({t, odom[i]});
    run.messages.push_back(RecordedMessage{"/odom", t, t, odometryMsg(t, odom[i])});
    if (next < test.size() && test[next] == i) {
      const LoggedScan& s = log.scans[i];
      run.messages.push_back(scanMessage(log, s, t));
      run.messages.push_back(RecordedMessage{"/ground_truth", t, t, poseMsg(t, s.pose)});
      run.truth.push_back({t, s.pose});
      ++next;
    }
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
