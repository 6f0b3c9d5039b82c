// The simulated robot base executing velocity commands as a real base does: commands are checked
// (nonsense rejected, the rest clamped to the limits), the velocity follows the last command
// within per-axis acceleration limits, a watchdog brings the base to a stop when commands cease,
// and the planar pose is integrated along circular arcs with each piece's mean velocity (exact at
// constant velocity, second order while it changes) in substeps of at most 10 ms.
#pragma once

#include <polyloc/config/robot.hpp>
#include <polyloc/geometry/pose.hpp>

#include <cstdint>
#include <string>

namespace polyloc {

struct BaseLimits {
  double max_v = 0.8;            // m/s, |vx| forward/backward
  double max_vy = 0.5;           // m/s, |vy| sideways (omni bases only)
  double max_w = 1.5;            // rad/s, |wz| turn rate
  double max_acc = 1.0;          // m/s^2, change of vx (speeding up and braking alike)
  double max_acc_y = 1.0;        // m/s^2, change of vy
  double max_acc_w = 3.0;        // rad/s^2, change of wz
  double command_timeout = 0.5;  // s without a command after which the base brakes to a stop
};

struct VelocityCommand {
  int64_t stamp_ns = 0;           // when the controller issued it (orders commands only)
  double vx = 0, vy = 0, wz = 0;  // base frame: m/s, m/s, rad/s
};

struct BaseTwist {
  double vx = 0, vy = 0, wz = 0;  // base frame: m/s, m/s, rad/s
};

class BaseMotion {
 public:
  // Throws std::invalid_argument naming the field when a limit is not finite and positive or
  // the start pose is not finite. The pose starts as start's planar projection.
  BaseMotion(Kinematics k, const BaseLimits& limits, const Pose& start, int64_t t0_ns);

  // A new target velocity, acting from the base's current time now() (a real base acts on a
  // command when it arrives; its watchdog also counts from then). Rejected, counted and
  // explained in `why` (field and value): NaN/inf, |value| beyond 100x its limit (at least 1),
  // a stamp older than the last accepted one or more than 1 s ahead of now(). Accepted commands
  // are clamped to the limits (counted); a differential base drops vy (counted when nonzero).
  bool command(const VelocityCommand& c, std::string* why = nullptr);
  // Moves the base to time t. A t before now() is ignored (counted).
  void advance(int64_t t_ns);
  // A collision: velocity zero at once, target zero until the next accepted command.
  void stop();
  // Puts the base at `p` (its planar part), velocity unchanged: a simulator moving the robot back
  // to where it stood before a contact. Throws std::invalid_argument for a non-finite pose.
  void place(const Pose& p);

  const Pose& pose() const { return pose_; }
  BaseTwist velocity() const { return vel_; }
  // No command for command_timeout s, or none yet: the watchdog holds the target at zero.
  bool commandTimedOut() const { return timed_out_; }
  int64_t now() const { return now_; }

  struct Counters {
    uint64_t accepted = 0, rejected = 0, clamped = 0, lateral_on_differential = 0;
    uint64_t timeouts = 0;        // watchdog stops (one per gap in the commands)
    uint64_t time_backwards = 0;  // advance() calls with a time before now()
  };
  const Counters& counters() const { return counters_; }

 private:
  void integrate(const BaseTwist& mean, double dt);

  Kinematics kin_;
  BaseLimits lim_;
  Pose pose_;
  double x_, y_, yaw_;  // the pose as integrated (yaw unwrapped)
  int64_t now_;
  int64_t last_rx_ns_ = 0;    // base time the last accepted command arrived
  int64_t last_stamp_ns_ = 0;
  bool has_stamp_ = false;
  bool timed_out_ = true;
  BaseTwist target_, vel_;  // target: the last command, zero after the watchdog or stop()
  Counters counters_;
};

}  // namespace polyloc
