#include <polynav/controller.hpp>

#include <polynav/scan_tools.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polynav {

namespace {

double wrap(double a) { return std::remainder(a, 2 * M_PI); }

Eigen::Vector2d toBase(const Eigen::Vector3d& pose, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = p - pose.head<2>();
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
}

// The pose after `dt` s at (v, w) from `p`.
Eigen::Vector3d predict(const Eigen::Vector3d& p, double v, double w, double dt) {
  const double yaw = p.z() + w * dt / 2;
  return {p.x() + v * dt * std::cos(yaw), p.y() + v * dt * std::sin(yaw), p.z() + w * dt};
}

}  // namespace

const char* phaseName(Phase p) {
  switch (p) {
    case Phase::Leave: return "leaving the last goal";
    case Phase::Recover: return "recovering (backing up)";
    case Phase::Follow: return "following the path";
    case Phase::DoorAlign: return "aligning in front of the door";
    case Phase::DoorPass: return "passing the door";
    case Phase::Approach: return "approaching the goal";
    case Phase::Dock: return "docking";
    case Phase::Align: return "aligning at the goal";
    case Phase::Reached: return "goal reached";
    case Phase::Failed: return "goal failed";
    case Phase::Done: return "all goals done";
  }
  return "?";
}

Controller::Controller(const LoadedGrid& grid, Zones zones, const ControllerConfig& config, LocalPlanner local)
    : raw_(grid.grid), zones_(std::move(zones)), cfg_(config), local_(std::move(local)), wave_(cfg_.plan) {
  if (!local_) throw std::invalid_argument("Controller: no local planner");
  for (size_t i = 0; i < grid.danger.size() && i < raw_.occupied.size(); ++i)
    if (grid.danger[i]) raw_.occupied[i] = 1;
  markDanger(zones_, raw_);
  markDoors(zones_, raw_);
  hull_ = RectHull::fromFootprint(cfg_.footprint);
  inflated_ = inflate(raw_, std::max(hull_.left, hull_.right) + cfg_.plan_margin);
  map_distance_ = obstacleDistance(raw_);
  for (const DangerZone& d : zones_.danger) danger_.push_back(d.polygon);
}

void Controller::setGoals(std::vector<GoalSpot> goals) {
  goals_ = std::move(goals);
  goal_ = 0;
  phase_ = Phase::Follow;
  goal_t0_ = -1;
}

void Controller::startGoal(double t, bool leave) {
  goal_t0_ = t;
  phase_t_ = t;
  phase_ = leave ? Phase::Leave : Phase::Follow;
  follow_ = PathFollow();
  planned_t_ = -1e9;
  blocked_since_ = -1;
  turning_ = false;
  stall_t_ = -1;
}

std::string Controller::where(const Eigen::Vector2d& p) const {
  const std::string room = zones_.roomAt(p);
  return room.empty() ? std::string("(no room)") : room;
}

bool Controller::plan(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double t, std::string* why) {
  blocked_.age(t, wave_.config().blocked_max_age_s);  // the documented key, not a second literal
  WavefrontPlan p = wave_.plan(inflated_, blocked_, from, to);
  if (!p.reachable && p.why == "start in an obstacle") {
    // Standing closer to the map than the inflation (after a door, beside a table): plan from
    // the nearest free cell within 1 m and go there first.
    std::optional<size_t> best;
    double best_d = 1.0;
    const auto c = inflated_.cellAt(from);
    if (c) {
      const long r = long(std::ceil(1.0 / inflated_.resolution)), cx = long(*c % inflated_.width), cy = long(*c / inflated_.width);
      for (long dy = -r; dy <= r; ++dy)
        for (long dx = -r; dx <= r; ++dx) {
          const long x = cx + dx, y = cy + dy;
          if (x < 0 || y < 0 || x >= long(inflated_.width) || y >= long(inflated_.height)) continue;
          const size_t i = inflated_.index(size_t(x), size_t(y));
          const double d = (inflated_.centre(i) - from).norm();
          if (!inflated_.occupied[i] && !blocked_.blocked(i) && d < best_d) best_d = d, best = i;
        }
    }
    if (best) {
      p = wave_.plan(inflated_, blocked_, inflated_.centre(*best), to);
      if (p.reachable) p.path.insert(p.path.begin(), from);
    }
  }
  if (!p.reachable) {
    if (why) *why = p.why;
    return false;
  }
  follow_ = PathFollow(p.path);
  planned_t_ = t;
  return true;
}

NavOutput Controller::finish(const NavInput& in, bool reached, const std::string& why) {
  phase_ = reached ? Phase::Reached : Phase::Failed;
  phase_t_ = in.t;
  NavOutput o;
  o.phase = phase_;
  o.state = reached ? 2 : 3;
  o.goal = goal_;
  o.status = where(in.pose.head<2>()) + ": '" + goals_[goal_].name + "' " + (reached ? "reached" : "failed: " + why);
  return o;
}

NavOutput Controller::turnTo(const NavInput& in, double yaw, double tolerance, bool* aligned) {
  NavOutput o;
  const double err = wrap(yaw - in.pose.z());
  *aligned = std::abs(err) < tolerance;
  if (!*aligned) {
    const double w = std::clamp(2.0 * err, -cfg_.max_yaw_rate, cfg_.max_yaw_rate);
    o.w = std::copysign(std::max(std::abs(w), 0.04), err);
  }
  return o;
}

NavOutput Controller::toPoint(const NavInput& in, const PolarScan& scan, const Eigen::Vector2d& target, double speed) {
  NavOutput o;
  const LocalStep l = local_(scan, toBase(in.pose, target));
  // Stalled (the local planner sees no way and no turn): turn towards the target, if the
  // corners clear; the guard decides.
  if (std::abs(l.v) < 0.005 && std::abs(l.w) < 0.005 && (target - in.pose.head<2>()).norm() > 0.05) {
    o = goTo(in, target, std::min(speed, 0.1));
    o.v = 0;
    o.clearance = l.min_clearance;
    situation_ = l.situation + ", stalled";
    return o;
  }
  o.v = std::min(l.v, speed);
  o.w = l.w;
  o.clearance = l.min_clearance;
  situation_ = l.situation;
  return o;
}

NavOutput Controller::goTo(const NavInput& in, const Eigen::Vector2d& target, double speed) {
  NavOutput o;
  const Eigen::Vector2d d = target - in.pose.head<2>();
  const double err = wrap(std::atan2(d.y(), d.x()) - in.pose.z());
  o.w = std::clamp(2.0 * err, -cfg_.max_yaw_rate, cfg_.max_yaw_rate);
  o.v = std::abs(err) > 0.35 ? 0.0 : std::clamp(0.8 * d.norm(), 0.02, speed);
  return o;
}

NavOutput Controller::alongLine(const NavInput& in, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double speed,
                                bool* arrived) {
  NavOutput o;
  const Eigen::Vector2d a = from.head<2>(), d = to.head<2>() - a;
  const double len = d.norm();
  const Eigen::Vector2d u = len > 1e-9 ? Eigen::Vector2d(d / len) : Eigen::Vector2d(std::cos(to.z()), std::sin(to.z()));
  const Eigen::Vector2d rel = in.pose.head<2>() - a;
  const double along = rel.dot(u), remaining = len - along;
  *arrived = remaining <= 0.003;
  if (*arrived) return o;
  // Pure pursuit on the line: a point 0.3 m ahead of the projection (the end at most).
  const Eigen::Vector2d aim = a + u * std::min(len + 0.05, along + 0.3);
  const double heading = std::atan2(aim.y() - in.pose.y(), aim.x() - in.pose.x());
  const double err = wrap(heading - in.pose.z());
  o.w = std::clamp(2.0 * err, -cfg_.max_yaw_rate, cfg_.max_yaw_rate);
  // Straight on: slow to a stop at the end; turn first when far off the line's direction.
  o.v = std::abs(err) > 0.35 ? 0.0 : std::clamp(0.8 * remaining, 0.015, speed);
  return o;
}

void Controller::guard(const NavInput& in, const PolarScan& scan, NavOutput& o, double stop_gap) const {
  if (o.v > 0) {
    const double free = freeTravel(scan, hull_, true);
    if (free < stop_gap) o.v = 0;
    else if (free < cfg_.slow_gap) o.v = std::min(o.v, std::max(0.05, cfg_.max_speed * (free - stop_gap) / (cfg_.slow_gap - stop_gap)));
  } else if (o.v < 0 && freeTravel(scan, hull_, false) < 0.05) {
    o.v = 0;
  }
  // Turning in place: the corners sweep wider than the sides (the next 0.4 s of turning).
  if (o.w != 0 && std::abs(o.v) < 0.05 && !rotationClear(scan, hull_, o.w * 0.4)) o.w = 0;
  // Never into a danger zone: look half a second ahead at the command, then at turning alone.
  if (!zones_.danger.empty() && zones_.inDanger(cfg_.footprint, predict(in.pose, o.v, o.w, 0.5))) {
    o.v = 0;
    if (zones_.inDanger(cfg_.footprint, predict(in.pose, 0, o.w, 0.5))) o.w = 0;
  }
}

NavOutput Controller::follow(const NavInput& in, const PolarScan& scan) {
  const Eigen::Vector2d pos = in.pose.head<2>();
  const GoalSpot& g = goals_[goal_];
  const Eigen::Vector3d a = approachPose(g);
  std::string why;
  if (follow_.empty() || in.t - planned_t_ > cfg_.replan_period || follow_.update(pos) > cfg_.off_path) {
    if (!plan(pos, a.head<2>(), in.t, &why)) {
      if (blocked_.size() == 0) return finish(in, false, "no path: " + why);
      if (blocked_since_ < 0) blocked_since_ = in.t;
      if (in.t - blocked_since_ > cfg_.wait_blocked) return finish(in, false, "path blocked: " + why);
      NavOutput o;
      o.status = where(pos) + ": waiting, the way to '" + g.name + "' is blocked";
      return o;
    }
    blocked_since_ = -1;
    follow_.update(pos);
  }
  // The VRS against the next metres of the path: an obstacle the map does not have, seen there
  // for a second, closes those cells (doors excepted: a closed door is reported) and replans.
  // Points within 10 cm of the map's own obstacles are the map (a door frame seen with range
  // noise beside a path that bends through the door), not an obstacle on the path.
  std::vector<Eigen::Vector2d> unmapped;
  for (const Eigen::Vector2d& p : scanPoints(in.scan, in.pose)) {
    const auto c = raw_.cellAt(p);
    if (c && map_distance_[*c] > 0.1f) unmapped.push_back(p);
  }
  Eigen::Vector2d at;
  const double hit = obstructedAt(unmapped, follow_.path(), follow_.segment(), cfg_.check_ahead,
                                  std::max(hull_.left, hull_.right), &at);
  if (hit >= 0) {
    if (!obstruction_ || (at - *obstruction_).norm() > 0.3) obstruction_ = at, obstruction_t_ = in.t;
    else if (in.t - obstruction_t_ > 1.0) {
      std::vector<size_t> cells;
      const double r = 0.15;
      for (double dy = -r; dy <= r + 1e-9; dy += raw_.resolution)
        for (double dx = -r; dx <= r + 1e-9; dx += raw_.resolution)
          if (auto c = raw_.cellAt(at + Eigen::Vector2d(dx, dy))) cells.push_back(*c);
      std::sort(cells.begin(), cells.end());
      cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
      const std::vector<size_t> doors = blocked_.block(inflated_, cells, in.t);
      obstruction_.reset();
      if (!doors.empty()) {
        const auto d = zones_.doorAt(at);
        return finish(in, false, "door " + (d ? "'" + zones_.doors[*d].name + "' " : std::string()) + "closed");
      }
      follow_ = PathFollow();  // replan next time
    }
  } else {
    obstruction_.reset();
  }
  // A door ahead: the path crosses a door's wall line through its opening within 1.5 m. Align
  // in front of it first. (Being in a door region is not enough: just through a door, the
  // region still holds the robot and the path leads away from it.)
  for (size_t k = 0; k < zones_.doors.size(); ++k) {
    const Door& d = zones_.doors[k];
    if (d.closed) continue;
    double prev = 0;
    for (double s = 0; s <= 1.5 + 1e-9; s += 0.05) {
      const Eigen::Vector2d q = follow_.carrot(s);
      const double side = (q - d.centre).dot(d.normal());
      if (s > 0 && (side > 0) != (prev > 0) && std::abs((q - d.centre).dot(d.along)) <= d.width / 2 + 0.2) {
        door_ = k;
        passage_ = doorPassage(d, pos);
        phase_ = Phase::DoorAlign;
        phase_t_ = in.t;
        turning_ = false;
        NavOutput o;
        o.status = where(pos) + ": door '" + d.name + "' ahead";
        return o;
      }
      prev = side;
    }
  }
  if (follow_.remaining() < 0.15 && (pos - a.head<2>()).norm() < 0.25) {
    phase_ = Phase::Approach;
    phase_t_ = in.t;
    turning_ = false;
    return NavOutput{};
  }
  // Corridors: look further along the axis, so the robot drives parallel and corrects drift
  // slowly; curves: closer and slower, so the orientation stays tangential to the path.
  double ahead = cfg_.lookahead, speed = cfg_.max_speed;
  std::string zone;
  const double turn = follow_.turnAhead(1.0);
  if (turn > cfg_.curve_angle) ahead *= 0.7, speed = cfg_.curve_speed, zone = "curve";
  else if (auto c = zones_.corridorAt(pos); c && std::abs(zones_.corridors[*c].axis.dot(follow_.direction(0.5))) > 0.97)
    ahead *= 1.5, zone = "corridor";
  if (zones_.doorAt(pos)) speed = std::min(speed, cfg_.door_speed), zone = "door";
  NavOutput o = toPoint(in, scan, follow_.carrot(ahead), speed);
  o.status = where(pos) + ": to '" + g.name + "'" + (zone.empty() ? "" : " (" + zone + ")") + " [" + situation_ + "]";
  return o;
}

NavOutput Controller::update(const NavInput& in) {
  NavOutput o;
  if (done()) {
    o.state = 0, o.phase = Phase::Done, o.goal = goals_.size(), o.status = "all goals done";
    return o;
  }
  const Eigen::Vector2d pos = in.pose.head<2>();
  if (goal_t0_ < 0) startGoal(in.t, false);
  if (!in.localised) {
    o.goal = goal_, o.status = "waiting for localisation";
    return o;
  }
  // Danger zones are obstacles to the local planner too, whether the VRS shows them or not.
  PolarScan scan = in.scan;
  addPolygons(scan, danger_, in.pose);
  // People walk on: their place in person_ahead seconds is kept clear too (an octagon each).
  std::vector<Polygon> people;
  for (const Person& p : in.people)
    for (double dt : {0.0, cfg_.person_ahead}) {
      const Eigen::Vector2d c = p.position + p.velocity * dt;
      if ((c - pos).norm() > 4.0) continue;
      Polygon oct;
      for (int k = 0; k < 8; ++k)
        oct.emplace_back(c + cfg_.person_radius * Eigen::Vector2d(std::cos(k * M_PI / 4), std::sin(k * M_PI / 4)));
      people.push_back(std::move(oct));
    }
  addPolygons(scan, people, in.pose);
  const GoalSpot& g = goals_[goal_];
  const Eigen::Vector3d a = approachPose(g);
  if ((phase_ != Phase::Reached && phase_ != Phase::Failed) && in.t - goal_t0_ > cfg_.mission_timeout)
    return finish(in, false, "timeout");
  double stop_gap = cfg_.stop_gap;
  bool ok = false;
  switch (phase_) {
    case Phase::Failed:  // reported with its reason by finish(): on to the next goal at once
      ++goal_;
      if (done()) return update(in);
      startGoal(in.t, false);
      return update(in);
    case Phase::Reached: {  // reported for `hold` s, then the next goal, backing out first
      o.state = 2;
      o.goal = goal_;
      o.phase = phase_;
      o.status = where(pos) + ": '" + g.name + "' reached";
      if (in.t - phase_t_ >= cfg_.hold) {
        ++goal_;
        if (!done()) startGoal(in.t, true);
      }
      return o;
    }
    case Phase::Leave: {  // straight back out to the last goal's intermediate pose
      const GoalSpot& last = goals_[goal_ - 1];
      const Eigen::Vector3d back = approachPose(last);
      const double remaining = (back.head<2>() - pos).dot(-Eigen::Vector2d(std::cos(last.pose.z()), std::sin(last.pose.z())));
      if (remaining <= 0.01) {
        phase_ = Phase::Follow;
        break;
      }
      o.v = -std::clamp(0.8 * remaining, 0.03, cfg_.dock_speed * 1.5);
      o.w = std::clamp(2.0 * wrap(last.pose.z() - in.pose.z()), -0.3, 0.3);
      o.status = where(pos) + ": backing out from '" + last.name + "'";
      break;
    }
    case Phase::Recover: {  // stalled for a while: back up a little, then plan again
      const double moved = (pos - stall_at_).norm();
      if (moved >= 0.3 || in.t - phase_t_ > 6.0) {
        phase_ = Phase::Follow, follow_ = PathFollow(), turning_ = false;
        break;
      }
      o.v = -0.1;
      o.status = where(pos) + ": stalled, backing up";
      break;
    }
    case Phase::Follow:
      o = follow(in, scan);
      if (phase_ == Phase::Failed) return o;  // finish(): state 3 with the reason, as it is
      break;
    case Phase::DoorAlign: {
      const Eigen::Vector2d p = passage_.before.head<2>();
      const double dist = (pos - p).norm();
      if (!turning_ && dist > 0.4) o = toPoint(in, scan, p, cfg_.door_speed * 1.5);
      else if (!turning_ && dist > 0.04) o = goTo(in, p, cfg_.door_speed);
      else if (turning_ = true, o = turnTo(in, passage_.before.z(), 0.05, &ok); ok) phase_ = Phase::DoorPass, turning_ = false;
      o.status = where(pos) + ": aligning in front of door '" + zones_.doors[door_].name + "'";
      break;
    }
    case Phase::DoorPass: {  // centred and slow, forwards only: no back-and-forth in the door
      o = alongLine(in, passage_.before, passage_.after, cfg_.door_speed, &ok);
      o.v = std::max(0.0, o.v);
      if (ok) phase_ = Phase::Follow, follow_ = PathFollow();
      o.status = where(pos) + ": passing door '" + zones_.doors[door_].name + "'";
      break;
    }
    case Phase::Approach:  // the last decimetres straight at the intermediate pose, then turn to the goal
      stop_gap = 0.05;  // the pose lies in the planner's free space: clear of the map by the inflation
      if (!turning_ && (pos - a.head<2>()).norm() > 0.03) o = goTo(in, a.head<2>(), cfg_.door_speed);
      else if (turning_ = true, o = turnTo(in, g.pose.z(), 0.03, &ok); ok) phase_ = Phase::Dock, turning_ = false;
      o.status = where(pos) + ": approaching '" + g.name + "'";
      break;
    case Phase::Dock:
      o = alongLine(in, a, g.pose, cfg_.dock_speed, &ok);
      stop_gap = 0.02;  // the goal is meant to be close to the furniture
      if (ok) phase_ = Phase::Align;
      o.status = where(pos) + ": docking at '" + g.name + "'";
      break;
    case Phase::Align:
      o = turnTo(in, g.pose.z(), cfg_.goal_yaw_tolerance, &ok);
      if (ok) return finish(in, true, "");
      o.status = where(pos) + ": aligning at '" + g.name + "'";
      break;
    case Phase::Done: return o;
  }
  guard(in, scan, o, stop_gap);
  // Standing still where it should drive (a gap the local planner will not enter, an obstacle
  // that does not go): after a few seconds, back up and plan again.
  const bool driving = phase_ == Phase::Follow || phase_ == Phase::DoorAlign || phase_ == Phase::Approach ||
                       phase_ == Phase::DoorPass;
  if (driving && std::abs(o.v) < 0.005 && std::abs(o.w) < 0.005) {
    if (stall_t_ < 0) stall_t_ = in.t;
    // In a door passage the way is the door: standing there for wait_blocked, it is closed.
    else if (phase_ == Phase::DoorPass && in.t - stall_t_ > cfg_.wait_blocked)
      return finish(in, false, "door '" + zones_.doors[door_].name + "' blocked");
    else if (phase_ != Phase::DoorPass && in.t - stall_t_ > cfg_.stall_time)
      phase_ = Phase::Recover, phase_t_ = in.t, stall_at_ = pos, stall_t_ = -1;
  } else {
    stall_t_ = -1;
  }
  o.phase = phase_;
  o.goal = goal_;
  o.state = 1;
  return o;
}

}  // namespace polynav
