// The robot's planar motion along a route: legs of smooth path (SplinePath through the
// densified waypoints) driven with a SpeedProfile, joined at stops where the robot waits and, if
// the next leg starts in another direction, turns in place. A differential robot faces along the
// path; an omni robot keeps the headings given at waypoints (interpolated along the path) or a
// fixed heading, or faces along the path when none is given.
#pragma once

#include <polyloc/config/robot.hpp>
#include <polyloc/sim/path.hpp>
#include <polyloc/sim/profile.hpp>

#include <optional>
#include <vector>

namespace polyloc {

struct Waypoint {
  Eigen::Vector2d p{0, 0};        // map frame, m
  std::optional<double> heading;  // rad; omni robots only
  double wait = 0;                // s to stand still here (implies stop)
  bool stop = false;              // end a leg here: stop, and turn in place if needed
};

struct RouteSpec {
  std::vector<Waypoint> waypoints;
  double max_speed = 0.5;                 // m/s
  double max_acceleration = 0.4;          // m/s^2
  double max_lateral_acceleration = 0.3;  // m/s^2, caps the speed in curves
  double max_yaw_rate = 0.8;              // rad/s, caps the speed in curves and turns in place
  double max_yaw_acceleration = 1.5;      // rad/s^2, turns in place
  double spacing = 0.5;                   // m, densification of the waypoints
  double start_pause = 1.0;               // s standing at the first waypoint
  std::optional<double> heading;          // omni: constant heading (rad)
};

struct PlanarState {
  double x = 0, y = 0, yaw = 0;
  double vx = 0, vy = 0;  // map frame, m/s
  double omega = 0;       // rad/s
  double s = 0;           // route arc length travelled, m
};

class Trajectory {
 public:
  // Throws std::invalid_argument for a route without waypoints or bad limits.
  Trajectory(const RouteSpec& route, Kinematics kinematics);

  double duration() const;  // s until the last waypoint is reached (and its wait is over)
  double length() const;    // m of path over all legs
  PlanarState at(double t) const;  // t in s from the start; holds the last state afterwards

  size_t numLegs() const { return legs_.size(); }
  const SplinePath& leg(size_t i) const { return legs_[i].path; }
  // Points along the whole path every `spacing` metres (plots, clearance checks), with yaw.
  std::vector<PlanarState> sample(double spacing) const;

 private:
  struct Leg {
    SplinePath path;
    SpeedProfile profile;
    double s0;  // route arc length at the start of the leg
  };
  struct Phase {
    enum Kind { Pause, Drive, Turn } kind;
    double t0, t1;
    size_t leg = 0;                 // Drive
    double x = 0, y = 0, yaw0 = 0;  // Pause, Turn
    double dyaw = 0, s = 0;         // Turn: signed angle; Pause/Turn: route arc length
  };
  double headingOn(size_t leg, double s) const;  // at leg arc length s
  double headingSlope(size_t leg, double s) const;

  Kinematics kin_;
  RouteSpec route_;
  std::vector<Leg> legs_;
  std::vector<Phase> phases_;
  std::vector<std::pair<double, double>> anchors_;  // omni: (route s, unwrapped heading)
};

}  // namespace polyloc
