#include <polyloc/sim/drive.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {

namespace {

const DriveOptions& checked(const DriveOptions& o) {
  auto positive = [](double v, const char* name) {
    if (!std::isfinite(v) || v <= 0) throw std::invalid_argument(fmt::format("DriveOptions.{} = {}: must be > 0", name, v));
  };
  positive(o.collision_step, "collision_step");
  positive(o.collision_merge, "collision_merge");
  if (!std::isfinite(o.give_way) || o.give_way < 0)
    throw std::invalid_argument(fmt::format("DriveOptions.give_way = {}: must be >= 0 m", o.give_way));
  if (!std::isfinite(o.command_latency) || o.command_latency < 0 || o.command_latency > 1)
    throw std::invalid_argument(fmt::format("DriveOptions.command_latency = {}: must be in [0, 1] s", o.command_latency));
  return o;
}

// The route's first waypoint, heading navigation.start_yaw: the route itself is not driven.
Pose startPose(const Scenario& s) {
  const Waypoint& w = s.route.waypoints.at(0);
  return Pose::planar(w.p.x(), w.p.y(), s.navigation.start_yaw);
}

}  // namespace

DriveSim::DriveSim(Simulator& sim, const DriveOptions& options)
    : sim_(sim),
      opt_(checked(options)),
      stepper_(sim),
      base_(sim.scenario().config.robot.kinematics, options.limits, startPose(sim.scenario()), 0),
      body_(sim.world(), sim.scenario().config.robot, options.floor_clearance),
      last_clear_(base_.pose()) {}

DriveSim::~DriveSim() = default;

int64_t DriveSim::nextEventNs() const { return stepper_.nextEventNs(); }

void DriveSim::command(const VelocityCommand& c) {
  const int64_t at = c.stamp_ns + std::llround(opt_.command_latency * 1e9);
  pending_.emplace_back(std::max(at, base_.now()), c);
}

PlanarState DriveSim::planar() const {
  PlanarState s;
  const Pose& p = base_.pose();
  s.x = p.x(), s.y = p.y(), s.yaw = p.yaw();
  const BaseTwist v = base_.velocity();
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  s.vx = c * v.vx - sn * v.vy, s.vy = sn * v.vx + c * v.vy, s.omega = v.wz;
  return s;
}

Pose DriveSim::truth() const { return sim_.floor().pose(planar()); }

void DriveSim::moveTo(int64_t t_ns) {
  const int64_t step = std::max<int64_t>(1, std::llround(opt_.collision_step * 1e9));
  while (base_.now() < t_ns) {
    int64_t next = std::min(t_ns, base_.now() + step);
    if (!pending_.empty() && pending_.front().first <= next) next = std::max(base_.now(), pending_.front().first);
    const int64_t before = base_.now();
    base_.advance(next);
    while (!pending_.empty() && pending_.front().first <= base_.now()) {
      std::string why;
      if (!base_.command(pending_.front().second, &why)) last_rejection_ = why;
      pending_.pop_front();
    }
    const Pose here = truth();
    const double t = double(base_.now()) * 1e-9;
    giveWay(t, {here.x(), here.y()}, double(base_.now() - before) * 1e-9);
    const PeopleScene people = sim_.people().scene(t, {here.x(), here.y()});
    const BodyContact contact = body_.check(here, &people);
    if (!contact.hit) {
      last_clear_ = base_.pose();
      continue;
    }
    ++contacts_;
    if (contact.what == "person") {
      // The robot's fault only when it moves towards the contact (2 cm/s and more).
      const BaseTwist v = base_.velocity();
      const double c = std::cos(here.yaw()), s = std::sin(here.yaw());
      const Eigen::Vector2d vel(c * v.vx - s * v.vy, s * v.vx + c * v.vy);
      const Eigen::Vector2d to(contact.where.x() - here.x(), contact.where.y() - here.y());
      if (vel.dot(to.normalized()) < 0.02) {
        if (t - last_struck_t_ > opt_.collision_merge) struck_.push_back({t, here, contact});
        last_struck_t_ = t;
        last_clear_ = base_.pose();
        continue;
      }
    }
    if (t - last_contact_t_ > opt_.collision_merge) collisions_.push_back({t, here, contact});
    last_contact_t_ = t;
    base_.stop();
    base_.place(last_clear_);
  }
}

void DriveSim::giveWay(double t, const Eigen::Vector2d& robot, double dt) {
  People& people = sim_.people();
  if (people.size() == 0 || !(opt_.give_way > 0) || dt <= 0) return;
  std::vector<double> delays = people.delays();
  delays.resize(people.size(), 0.0);
  bool changed = false;
  for (size_t i = 0; i < people.size(); ++i) {
    const PersonState s = people.state(i, t, robot);
    const Eigen::Vector2d v(s.vx, s.vy);
    if (!s.present || v.norm() < 1e-3) continue;
    const Eigen::Vector2d dir = v.normalized(), rel = robot - Eigen::Vector2d(s.x, s.y);
    const double ahead = rel.dot(dir), lateral = std::abs(dir.x() * rel.y() - dir.y() * rel.x());
    if (ahead > 0 && ahead < opt_.give_way && lateral < 0.6) delays[i] += dt, changed = true;
  }
  if (changed) people.setDelays(std::move(delays));
}

void DriveSim::step(RecordingWriter& out, const SimHooks& hooks) {
  moveTo(stepper_.nextEventNs());
  stepper_.emit(planar(), out, hooks);
}

}  // namespace polyloc
