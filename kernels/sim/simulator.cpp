#include <polyloc/io/message_pose.hpp>
#include <polyloc/map/load.hpp>
#include <polyloc/raycast/embree.hpp>
#include <polyloc/sim/odometry.hpp>
#include <polyloc/sim/simulator.hpp>

#include "sensor_sim.hpp"
#include "truth_topics.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace polyloc {

namespace {

constexpr int64_t kChunkNs = 1000000000;  // simulated per batch
enum Order : int { kOrderStatic = 0, kOrderTf = 1, kOrderOdom = 2, kOrderTruth = 3 };
constexpr uint64_t kTruthVrsEvery = 5;  // frames of the first level scanner per /ground_truth/vrs

int64_t tickNs(uint64_t k, double rate_hz) { return std::llround(static_cast<double>(k) * 1e9 / rate_hz); }

}  // namespace

Mesh loadScenarioMap(const Scenario& s) { return loadMesh(s.config.map.file, s.config.map.load); }

Simulator::Simulator(Scenario scenario, Mesh map) : scenario_(std::move(scenario)) {
  const Scenario& s = scenario_;
  const Rig& rig = s.config.rig;
  if (rig.sensors.empty()) throw std::invalid_argument("simulator: the rig has no sensors");
  if (!(s.odometry.rate_hz > 0)) throw std::invalid_argument("simulator: odometry rate must be positive");
  for (const Sensor& sensor : rig.sensors)
    if (!(sensor.rateHz() > 0)) throw std::invalid_argument("simulator: sensor " + sensor.name + " has no rate");
  trajectory_ = std::make_unique<Trajectory>(s.route, s.config.robot.kinematics);
  const Mesh base = s.world.mesh.empty() ? std::move(map) : loadMesh(s.world.mesh, s.config.map.load);
  world_ = moveChairs(base, s.chairs, s.seed, &chair_moves_);
  if (!s.world.empty()) {
    std::vector<Eigen::Vector2d> route;
    for (const PlanarState& p : trajectory_->sample(0.1)) route.emplace_back(p.x, p.y);
    world_ = buildWorld(world_, s.world, s.seed, route, &world_changes_);
  }
  person_label_ = world_.labelId("person");
  auto caster = std::make_unique<EmbreeCaster>(world_);
  // Surfaces are surfaces from both sides: beams go on through glass panes (entering and
  // leaving them) and floor probes through furniture; no beam starts inside a solid otherwise.
  caster->options.backface_is_solid = false;
  caster_ = std::move(caster);
  people_ = std::make_unique<People>(s.people);
  floor_ = std::make_unique<FloorModel>(s.floor, *caster_, world_, s.config.robot.contactPoints(), s.seed);
  duration_ = s.duration > 0 ? s.duration : trajectory_->duration() + 1.0;

  std::vector<SensorNoise> noise = s.noise.sensors;
  const std::vector<SensorNoise> defaults = defaultSensorNoise(rig);
  for (size_t i = noise.size(); i < rig.size(); ++i) noise.push_back(defaults[i]);
  detail::SensorSimOptions opt;
  opt.noise_enabled = s.noise.enabled;
  opt.glass = s.noise.glass;
  opt.max_bounces = s.noise.max_bounces;
  opt.seed = s.seed;
  for (size_t i = 0; i < rig.size(); ++i) {
    sensors_.push_back(std::make_unique<detail::SensorSim>(i, rig.sensors[i], noise[i], opt, world_, person_label_));
    sensor_beams_.push_back(rig.sensors[i].beams());
    const Sensor& r = rig.sensors[i];
    if (std::holds_alternative<PlanarScannerSpec>(r.spec) && std::abs(r.mount.roll()) < 0.17 && std::abs(r.mount.pitch()) < 0.17)
      level_scanners_.push_back(int(i));  // within 10 deg of level: they see people's legs
  }
}

Simulator::~Simulator() = default;

const RayCaster& Simulator::caster() const { return *caster_; }

Pose Simulator::groundTruth(double t) const { return floor_->pose(trajectory_->at(t)); }

namespace detail {
// Where a simulation stands between spans: the next odometry tick and the next frame of every
// sensor, and the odometry integrated so far.
struct SimCursor {
  SimCursor(const Scenario& s, size_t sensors) : odo(s.odometry.noise, s.noise.enabled, s.seed), next_frame(sensors, 0) {}
  OdometrySimulator odo;
  uint64_t next_tick = 0;
  std::vector<uint64_t> next_frame;
  int64_t last_tick_ns = 0;
  bool static_written = false;
};
}  // namespace detail

SimSummary Simulator::run(RecordingWriter& out, const SimHooks& hooks) {
  SimSummary summary;
  const int64_t end_ns = std::llround(duration_ * 1e9);
  detail::SimCursor cur(scenario_, sensors_.size());
  const auto along_route = [&](int64_t t) { return trajectory_->at(static_cast<double>(t) * 1e-9); };
  for (int64_t c0 = 0; c0 <= end_ns; c0 += kChunkNs) {
    const int64_t c1 = std::min(c0 + kChunkNs, end_ns + 1);
    span(c1, along_route, cur, out, hooks, summary);
    if (hooks.on_progress) hooks.on_progress(std::min(1.0, static_cast<double>(c1) / static_cast<double>(end_ns + 1)));
  }
  summary.sim_duration_s = duration_;
  summary.floor_misses = floor_->misses();
  summary.chairs_moved = chair_moves_.size();
  summary.world = world_changes_;
  return summary;
}

void Simulator::span(int64_t c1, const std::function<PlanarState(int64_t)>& state_at, detail::SimCursor& cur,
                     RecordingWriter& out, const SimHooks& hooks, SimSummary& summary) {
  const Scenario& s = scenario_;
  const int64_t t0 = s.start_time_ns;
  const double odo_rate = s.odometry.rate_hz;
  auto write = [&](const std::string& topic, int64_t stamp, const msg::Message& m) {
    out.write(topic, stamp, m);
    ++summary.topics[topic];
    ++summary.messages;
  };
  if (!cur.static_written) {  // mounts, once
    msg::TFMessage tf;
    for (const auto& sensor : sensors_) sensor->staticTransforms(s.base_frame, t0, tf.transforms);
    write("/tf_static", t0, tf);
    cur.static_written = true;
  }
  OdometrySimulator& odo = cur.odo;
  uint64_t& next_tick = cur.next_tick;
  std::vector<uint64_t>& next_frame = cur.next_frame;
  int64_t& last_tick_ns = cur.last_tick_ns;
  // Events of this chunk and the robot's true pose at each.
  std::vector<int64_t> ticks;
  for (; tickNs(next_tick, odo_rate) < c1; ++next_tick) ticks.push_back(tickNs(next_tick, odo_rate));
  std::vector<std::vector<detail::FrameJob>> jobs(sensors_.size());
  std::vector<int64_t> times = ticks;
  for (size_t i = 0; i < sensors_.size(); ++i) {
    const double rate = sensors_[i]->rateHz();
    for (; tickNs(next_frame[i], rate) < c1; ++next_frame[i]) {
      detail::FrameJob job;
      job.frame.sensor = i;
      job.frame.index = next_frame[i];
      job.frame.stamp_ns = t0 + tickNs(next_frame[i], rate);
      job.frame.t = static_cast<double>(tickNs(next_frame[i], rate)) * 1e-9;
      jobs[i].push_back(std::move(job));
      times.push_back(tickNs(next_frame[i], rate));
    }
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::vector<PlanarState> states(times.size());
  for (size_t k = 0; k < times.size(); ++k) states[k] = state_at(times[k]);
  std::vector<Pose> truth(times.size());
  floor_->poses(states, truth.data());
  auto indexOf = [&](int64_t t) { return std::lower_bound(times.begin(), times.end(), t) - times.begin(); };

  std::vector<detail::OutMessage> msgs;
  for (int64_t tick : ticks) {
    const Pose& gt = truth[indexOf(tick)];
    if (tick == 0) odo.reset(gt);
    else odo.step(gt, static_cast<double>(tick - last_tick_ns) * 1e-9);
    last_tick_ns = tick;
    const int64_t stamp = t0 + tick;
    msg::TransformStamped tf;
    tf.header = {msg::fromNs(stamp), s.odom_frame};
    tf.child_frame_id = s.base_frame;
    tf.transform = toMsgTransform(odo.pose());
    msgs.push_back({stamp, kOrderTf, "/tf", msg::TFMessage{{tf}}});
    msg::Odometry od;
    od.header = {msg::fromNs(stamp), s.odom_frame};
    od.child_frame_id = s.base_frame;
    od.pose.pose = toMsgPose(odo.pose());
    const Eigen::Vector3d var = odo.variance();
    // x, y, yaw from the drift model; z, roll, pitch are not measured by wheel odometry.
    od.pose.covariance = {};
    for (int k : {14, 21, 28}) od.pose.covariance[k] = 1e6;
    od.pose.covariance[0] = var.x(), od.pose.covariance[7] = var.y(), od.pose.covariance[35] = var.z();
    od.twist.twist.linear = {odo.twist().x(), odo.twist().y(), 0};
    od.twist.twist.angular = {0, 0, odo.twist().z()};
    for (int k : {14, 21, 28}) od.twist.covariance[k] = 1e6;
    msgs.push_back({stamp, kOrderOdom, "/odom", std::move(od)});
    msg::PoseStamped ps;
    ps.header = {msg::fromNs(stamp), s.map_frame};
    ps.pose = toMsgPose(gt);
    msgs.push_back({stamp, kOrderTruth, "/ground_truth", ps});
    if (hooks.on_tick) hooks.on_tick(stamp, gt, odo.pose());
  }

  // People at every frame time (shared by the sensors of that time).
  std::map<int64_t, PeopleScene> scenes;
  if (people_->size() > 0)
    for (size_t k = 0; k < times.size(); ++k)
      scenes[times[k]] = people_->scene(static_cast<double>(times[k]) * 1e-9, {states[k].x, states[k].y});
  for (size_t i = 0; i < sensors_.size(); ++i) {
    for (detail::FrameJob& job : jobs[i]) {
      const int64_t rel = job.frame.stamp_ns - t0;
      job.frame.map_T_base = truth[indexOf(rel)];
      job.frame.map_T_sensor = sensors_[i]->sensor().worldPose(job.frame.map_T_base);
      if (!scenes.empty()) job.people = &scenes[rel];
    }
    sensors_[i]->simulate(*caster_, jobs[i]);
    for (detail::FrameJob& job : jobs[i])
      for (detail::OutMessage& m : job.messages) msgs.push_back(std::move(m));
  }
  // Ground truth for perception (truth_topics.hpp): the people at every frame of a level
  // scanner, the true VRS at every truth_vrs_every-th frame of the first one, ToF artefacts.
  const PeopleScene no_people;
  for (size_t i = 0; i < sensors_.size(); ++i) {
    const Sensor& sensor = sensors_[i]->sensor();
    for (const detail::FrameJob& job : jobs[i]) {
      const int64_t rel = job.frame.stamp_ns - t0;
      const PeopleScene& scene = scenes.empty() ? no_people : scenes[rel];
      if (std::holds_alternative<DepthCameraSpec>(sensor.spec)) {
        msgs.push_back(detail::artefactImage(job.frame, sensor, 10 + int(i)));
        continue;
      }
      if (!std::count(level_scanners_.begin(), level_scanners_.end(), int(i))) continue;
      if (people_->size() > 0)
        msgs.push_back(detail::peopleTruth(job.frame, sensor_beams_[i], *people_, scene, person_label_, s.map_frame, 10 + int(i)));
      if (int(i) == level_scanners_.front() && job.frame.index % kTruthVrsEvery == 0)
        msgs.push_back(detail::vrsTruth(job.frame, *caster_, scene, s.config.vrs, s.base_frame, 10 + int(i)));
    }
  }

  if (hooks.on_frame) {
    std::vector<const SimFrame*> frames;
    for (const auto& list : jobs)
      for (const auto& job : list) frames.push_back(&job.frame);
    std::stable_sort(frames.begin(), frames.end(), [](const SimFrame* a, const SimFrame* b) {
      return a->stamp_ns != b->stamp_ns ? a->stamp_ns < b->stamp_ns : a->sensor < b->sensor;
    });
    for (const SimFrame* f : frames) hooks.on_frame(*f);
  }
  std::stable_sort(msgs.begin(), msgs.end(), [](const detail::OutMessage& a, const detail::OutMessage& b) {
    return a.stamp != b.stamp ? a.stamp < b.stamp : a.order < b.order;
  });
  for (const detail::OutMessage& m : msgs) write(m.topic, m.stamp, m.message);
}

SimStepper::SimStepper(Simulator& sim) : sim_(sim), cur_(std::make_unique<detail::SimCursor>(sim.scenario(), sim.sensors_.size())) {}

SimStepper::~SimStepper() = default;

int64_t SimStepper::nextEventNs() const {
  int64_t t = tickNs(cur_->next_tick, sim_.scenario().odometry.rate_hz);
  for (size_t i = 0; i < sim_.sensors_.size(); ++i) t = std::min(t, tickNs(cur_->next_frame[i], sim_.sensors_[i]->rateHz()));
  return t;
}

void SimStepper::emit(const PlanarState& state, RecordingWriter& out, const SimHooks& hooks) {
  const int64_t t = nextEventNs();
  sim_.span(t + 1, [&](int64_t) { return state; }, *cur_, out, hooks, summary_);
}

}  // namespace polyloc
