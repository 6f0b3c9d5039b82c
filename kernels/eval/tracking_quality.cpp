#include <polyloc/eval/ground_truth.hpp>
#include <polyloc/eval/tracking_quality.hpp>
#include <polyloc/sim/simulator.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace polyloc {
namespace {

struct Frame {
  size_t sensor = 0;
  int64_t stamp_ns = 0;
  double t = 0;
  Pose map_T_base, map_T_sensor;
  std::vector<float> ranges;
  std::vector<uint32_t> beams_on;  // per person: beams that hit them within max_range
};

// The scenario with only the tracking scanners (the others cost simulation time, nothing else).
Scenario trackingScenario(const Scenario& s, const std::vector<size_t>& sensors, double duration) {
  Scenario out = s;
  out.config.rig.sensors.clear();
  out.config.rig.presets.clear();
  out.noise.sensors.clear();
  for (size_t i : sensors) {
    out.config.rig.add(s.config.rig.sensors[i], s.config.rig.presets[i]);
    if (i < s.noise.sensors.size()) out.noise.sensors.push_back(s.noise.sensors[i]);
  }
  if (out.noise.sensors.size() != out.config.rig.size()) out.noise.sensors = defaultSensorNoise(out.config.rig);
  if (duration > 0) out.duration = duration;
  return out;
}

Eigen::Vector2d xy(const Pose& T, const Eigen::Vector2d& p) { return (T * Eigen::Vector3d(p.x(), p.y(), 0)).head<2>(); }

}  // namespace

TrackingQuality evaluateTracking(const Scenario& scenario, const Mesh& map, const TrackingConfig& config_in,
                                 const TrackingEvalOptions& o, const std::function<void(double)>& progress) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const std::vector<size_t> used = trackingSensors(scenario.config.rig, config_in);
  const Scenario s = trackingScenario(scenario, used, o.duration);
  TrackingConfig config = config_in;
  config.sensors.clear();  // the reduced rig holds exactly the tracking scanners
  Simulator sim(s, map);
  const People& people = sim.people();
  const uint32_t person = sim.personLabel();
  std::vector<BeamSet> beams;
  for (const Sensor& sensor : s.config.rig.sensors) beams.push_back(sensor.beams());

  std::vector<StampedPose> odom;
  std::vector<Frame> frames;
  SimHooks hooks;
  hooks.on_tick = [&](int64_t stamp, const Pose&, const Pose& od) { odom.push_back({stamp, od}); };
  hooks.on_frame = [&](const SimFrame& f) {
    Frame fr{f.sensor, f.stamp_ns, f.t, f.map_T_base, f.map_T_sensor, f.measured, std::vector<uint32_t>(people.size(), 0)};
    const Eigen::Vector2d robot(f.map_T_base.x(), f.map_T_base.y());
    std::vector<PersonState> st(people.size());
    for (size_t i = 0; i < people.size(); ++i) st[i] = people.state(i, f.t, robot);
    const BeamSet& b = beams[f.sensor];
    for (size_t k = 0; k < f.label.size(); ++k) {
      if (f.label[k] != person || !(f.exact[k] <= o.range)) continue;
      const Eigen::Vector3d dir(b.dx[k], b.dy[k], b.dz[k]);
      const Eigen::Vector3d end = f.map_T_sensor * (double(f.exact[k]) * dir);
      size_t best = people.size();
      double best_d = 0.5;  // a beam on a body ends within 0.5 m of its centre line
      for (size_t i = 0; i < people.size(); ++i) {
        if (!st[i].present) continue;
        const double d = std::hypot(end.x() - st[i].x, end.y() - st[i].y);
        if (d < best_d) best_d = d, best = i;
      }
      if (best < people.size()) ++fr.beams_on[best];
    }
    frames.push_back(std::move(fr));
  };
  if (progress) hooks.on_progress = progress;
  NullRecordingWriter null;
  sim.run(null, hooks);
  std::stable_sort(frames.begin(), frames.end(), [](const Frame& a, const Frame& b) {
    return a.stamp_ns != b.stamp_ns ? a.stamp_ns < b.stamp_ns : a.sensor < b.sensor;
  });
  const GroundTruth odometry(odom);  // odom_T_base at any stamp

  TrackingQuality q;
  q.people = people.size();
  q.sim_duration_s = sim.duration();
  PeopleTracker tracker(s.config.rig, config);
  MotAccumulator mot(o.match_distance, o.forget_after), strict(o.match_distance, o.forget_after);
  double fastest = 0;
  for (const Sensor& sensor : s.config.rig.sensors) fastest = std::max(fastest, sensor.rateHz());
  const double dt = fastest > 0 ? 1.0 / fastest : 0.0;
  double tracking_s = 0;
  const int64_t tol = std::llround(config.sync_tolerance * 1e9);
  for (size_t a = 0; a < frames.size();) {
    size_t b = a;
    std::vector<uint32_t> beams_on(people.size(), 0);
    const auto c0 = Clock::now();
    for (; b < frames.size() && frames[b].stamp_ns <= frames[a].stamp_ns + tol; ++b) {
      const Frame& f = frames[b];
      Pose pose = f.map_T_sensor;
      if (o.odometry) {
        const auto od = odometry.at(f.stamp_ns);
        if (!od) continue;
        pose = *od * s.config.rig.sensors[f.sensor].mount;
      }
      tracker.addScan(f.sensor, f.stamp_ns, pose, f.ranges);
      for (size_t i = 0; i < people.size(); ++i) beams_on[i] += f.beams_on[i];
    }
    tracker.flush();
    tracking_s += std::chrono::duration<double>(Clock::now() - c0).count();

    // The tracker's frame -> map, through the robot: in odometry mode its drift is not the tracker's.
    const Frame& f = frames[a];
    Pose map_T_frame;
    if (o.odometry)
      if (const auto od = odometry.at(f.stamp_ns)) map_T_frame = f.map_T_base * od->inverse();
    const Pose frame_T_map = map_T_frame.inverse();
    std::vector<MotObject> gt, gt_strict, hyps;
    TrackingEvalFrame ef;
    ef.t = f.t, ef.map_T_base = f.map_T_base;
    const Eigen::Vector2d robot(f.map_T_base.x(), f.map_T_base.y());
    for (size_t i = 0; i < people.size(); ++i) {
      const PersonState p = people.state(i, f.t, robot);
      if (!p.present) continue;
      const bool visible = beams_on[i] >= o.min_beams;
      const bool walking = std::hypot(p.vx, p.vy) >= o.min_speed;
      const Eigen::Vector2d at(p.x, p.y);
      gt.push_back({i, xy(frame_T_map, at), visible && walking});
      gt_strict.push_back({i, xy(frame_T_map, at), visible});
      if (o.keep_frames) ef.truth.push_back({i, at, visible && walking});
    }
    for (const TrackState& t : tracker.tracks().items) {
      if (t.status != TrackStatus::Confirmed) continue;
      hyps.push_back({t.id, t.position, true});
      if (o.keep_frames) {
        TrackState m = t;
        m.position = xy(map_T_frame, t.position);
        ef.tracks.push_back(m);
      }
    }
    if (o.keep_frames)
      for (Detection d : tracker.detections()) {
        d.position = xy(map_T_frame, d.position);
        ef.detections.push_back(d);
      }
    mot.addFrame(dt, gt, hyps);
    strict.addFrame(dt, gt_strict, hyps);
    if (o.keep_frames) q.frames.push_back(std::move(ef));
    a = b;
  }
  q.mot = mot.metrics();
  q.strict = strict.metrics();
  q.counters = tracker.counters();
  q.tracking_s = tracking_s;
  q.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return q;
}

}  // namespace polyloc
