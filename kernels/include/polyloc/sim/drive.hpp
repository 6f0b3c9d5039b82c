// Closed-loop simulation: the simulated robot executes the velocity commands of a controller
// instead of the scenario's route. A BaseMotion (limits, acceleration, command timeout) moves it
// between the simulator's events, the body is checked against the world and the people every
// collision_step on the way, and each event's sensor frames are simulated where the robot then is.
// A contact stops the robot where it last stood clear (as a bumper stop would) and is recorded
// with where and what it touched; contacts in quick succession (pushing on) are one collision.
// Walking people stop while the robot stands in their way (give_way) and go on when it has gone;
// a person who still walks into a robot that stands or moves away from them is recorded apart
// (struckBy) and does not stop it: it is not the controller's collision.
#pragma once

#include <polyloc/sim/base_motion.hpp>
#include <polyloc/sim/body_collision.hpp>
#include <polyloc/sim/simulator.hpp>

#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace polyloc {

struct DriveOptions {
  BaseLimits limits;
  double command_latency = 0.05;  // s from the stamp of the data a command answers to the base acting on it
  double collision_step = 0.02;   // s between body checks while moving
  double floor_clearance = 0.02;  // m of the body's underside above the floor (BodyCollider)
  double collision_merge = 2.0;   // s: contacts closer in time than this count as one collision
  // m: a walking person stops while the robot stands within this distance ahead of them (and
  // 0.6 m of their line), as people give way; 0: they walk on through it
  double give_way = 1.0;
};

struct CollisionEvent {
  double t = 0;       // s from the start
  Pose pose;          // where the body touched (map_T_base)
  BodyContact contact;
};

class DriveSim {
 public:
  // Starts at the route's first waypoint heading navigation.start_yaw (the route is not driven). Throws std::invalid_argument for bad
  // options (naming the field), as BaseMotion and BodyCollider do for theirs.
  DriveSim(Simulator& sim, const DriveOptions& options = {});
  ~DriveSim();

  int64_t nextEventNs() const;  // from the start
  // A controller's command; `c.stamp_ns` from the start, the stamp of the data it answers. It acts
  // at that stamp + command_latency (or at once, when that time has passed), in the order given.
  // The base checks it when it acts: rejections are counted in base().counters(), the last
  // reason kept in lastRejection().
  void command(const VelocityCommand& c);
  // Moves the robot to the next event, checking the body on the way, and simulates that event.
  void step(RecordingWriter& out, const SimHooks& hooks = {});

  double nowS() const { return double(base_.now()) * 1e-9; }
  Pose truth() const;                       // map_T_base on the floor, now
  const BaseMotion& base() const { return base_; }
  const std::vector<CollisionEvent>& collisions() const { return collisions_; }
  uint64_t contacts() const { return contacts_; }  // body checks that touched (every one, merged or not)
  const std::vector<CollisionEvent>& struckBy() const { return struck_; }  // people walking into the robot
  const std::string& lastRejection() const { return last_rejection_; }
  const Simulator& simulator() const { return sim_; }

 private:
  void moveTo(int64_t t_ns);  // integrates with body checks
  void giveWay(double t, const Eigen::Vector2d& robot, double dt);  // people waiting for the robot
  PlanarState planar() const;

  Simulator& sim_;
  DriveOptions opt_;
  SimStepper stepper_;
  BaseMotion base_;
  BodyCollider body_;
  std::deque<std::pair<int64_t, VelocityCommand>> pending_;  // (act at, command)
  Pose last_clear_;
  std::vector<CollisionEvent> collisions_, struck_;
  double last_struck_t_ = -1e9;
  double last_contact_t_ = -1e9;
  uint64_t contacts_ = 0;
  std::string last_rejection_;
};

}  // namespace polyloc
