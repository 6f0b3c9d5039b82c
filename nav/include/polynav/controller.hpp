// The reference controller's decisions, one per VRS: the global path (wavefront on the map's grid,
// danger zones closed, replanned when the VRS finds it blocked), local avoidance towards a carrot
// on the path (Nearness Diagram or VFH on the VRS with the robot's rectangular hull), and the
// zones: door passages (align in front, pass centred and slow, never reverse inside), goal docking
// (intermediate pose, then straight in to 2 cm and 1 deg), corridors (look further along the
// axis), curves (slow, tangential), danger (virtual obstacles in the scan and a stop before any
// command that would take the footprint in). Pure: no I/O, no clock; the caller feeds it.
#pragma once

#include <polynav/grid_io.hpp>
#include <polynav/hull.hpp>
#include <polynav/path_follow.hpp>
#include <polynav/polar_scan.hpp>
#include <polynav/wavefront.hpp>
#include <polynav/zones.hpp>

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace polynav {

struct ControllerConfig {
  Polygon footprint{{0.3, 0.25}, {-0.3, 0.25}, {-0.3, -0.25}, {0.3, -0.25}};  // base_link
  double max_speed = 0.5;        // m/s
  double max_yaw_rate = 0.8;     // rad/s
  double door_speed = 0.2;       // m/s through a door region
  double curve_speed = 0.3;      // m/s where the path turns by more than curve_angle within 1 m
  double curve_angle = 0.6;      // rad
  double dock_speed = 0.12;      // m/s on the last straight to a goal
  double lookahead = 0.8;        // m: the carrot on the path (1.5x in corridors along the axis)
  double plan_margin = 0.05;     // m added to the hull's half width for the planning inflation
  double replan_period = 5.0;    // s
  double off_path = 0.6;         // m from the path: replan
  double check_ahead = 2.5;      // m of path checked against the VRS
  double stop_gap = 0.15;        // m free in front of the hull below which the robot stops
  double slow_gap = 1.0;         // m free in front of the hull below which it slows down
  double goal_tolerance = 0.02;  // m
  double goal_yaw_tolerance = 0.0087;  // rad (0.5 deg: a margin under the 1 deg asked)
  double mission_timeout = 120;  // s
  double hold = 1.0;             // s standing at a reached goal before the next one
  double wait_blocked = 20;      // s waiting for a blocked path to clear before giving up
  double stall_time = 3.0;       // s standing still while driving: back up 0.3 m and plan again
  double person_radius = 0.35;   // m: a walking person as the local planner keeps clear of them
  double person_ahead = 1.0;     // s: where a tracked person will be counts as an obstacle too
  WavefrontConfig plan;          // the global planner, and how long cells found blocked stay closed
};

// A local planner's answer: speeds and what it saw ("HSGR", "LS2", "vfh", ...).
struct LocalStep {
  double v = 0, w = 0;
  std::string situation;
  double min_clearance = 0;  // m between the hull and the nearest scan point
};
using LocalPlanner = std::function<LocalStep(const PolarScan& scan, const Eigen::Vector2d& goal_in_base)>;

enum class Phase { Leave, Recover, Follow, DoorAlign, DoorPass, Approach, Dock, Align, Reached, Failed, Done };
const char* phaseName(Phase p);

// A tracked person (polylocd's tracks, map frame).
struct Person {
  Eigen::Vector2d position{0, 0}, velocity{0, 0};
};

struct NavInput {
  double t = 0;                        // s, the data's time
  Eigen::Vector3d pose{0, 0, 0};       // estimate: x, y, yaw (map)
  bool localised = true;
  PolarScan scan;                      // the VRS
  std::vector<Person> people;          // confirmed tracks: kept clear of where they will be
};

struct NavOutput {
  double v = 0, w = 0;
  Phase phase = Phase::Follow;
  int state = 1;                       // 0 idle, 1 driving, 2 reached, 3 failed (POLYLOC_NAV_*)
  size_t goal = 0;                     // index into goals()
  std::string status;                  // "lab 1: door passage 'lab 1'"
  double clearance = 0;                // m: the local planner's smallest gap between hull and scan (trace)
};

class Controller {
 public:
  Controller(const LoadedGrid& grid, Zones zones, const ControllerConfig& config, LocalPlanner local);
  void setGoals(std::vector<GoalSpot> goals);
  NavOutput update(const NavInput& in);
  const std::vector<GoalSpot>& goals() const { return goals_; }
  bool done() const { return goal_ >= goals_.size(); }
  const PathFollow& path() const { return follow_; }
  size_t blockedCells() const { return blocked_.size(); }  // closed for the planner until they age

 private:
  void startGoal(double t, bool leave);
  bool plan(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double t, std::string* why);
  NavOutput follow(const NavInput& in, const PolarScan& scan);
  NavOutput toPoint(const NavInput& in, const PolarScan& scan, const Eigen::Vector2d& target, double speed);
  NavOutput goTo(const NavInput& in, const Eigen::Vector2d& target, double speed);  // turn, then straight at it
  NavOutput alongLine(const NavInput& in, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double speed, bool* arrived);
  NavOutput turnTo(const NavInput& in, double yaw, double tolerance, bool* aligned);
  NavOutput finish(const NavInput& in, bool reached, const std::string& why);
  void guard(const NavInput& in, const PolarScan& scan, NavOutput& out, double stop_gap) const;
  std::string where(const Eigen::Vector2d& p) const;

  NavGrid raw_, inflated_;
  std::vector<float> map_distance_;  // per cell of raw_: m to the nearest obstacle of the map
  Zones zones_;
  ControllerConfig cfg_;
  LocalPlanner local_;
  RectHull hull_;
  std::vector<Polygon> danger_;
  Wavefront wave_;
  BlockedCells blocked_;
  std::vector<GoalSpot> goals_;
  size_t goal_ = 0;
  Phase phase_ = Phase::Follow;
  PathFollow follow_;
  double goal_t0_ = -1, planned_t_ = -1e9, phase_t_ = 0, blocked_since_ = -1;
  DoorPassage passage_;
  size_t door_ = 0;
  std::optional<Eigen::Vector2d> obstruction_;  // where the path was last seen obstructed, and since when
  double obstruction_t_ = 0;
  std::string situation_;  // the local planner's last
  bool turning_ = false;
  double stall_t_ = -1;    // since when the robot stands where it should drive (-1: it does not)
  Eigen::Vector2d stall_at_{0, 0};   // DoorAlign/Approach: at the point, turning on the spot (no going back to driving)
};

}  // namespace polynav
