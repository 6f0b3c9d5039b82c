// What `polyloc eval nav` measures of each mission, from the simulator's truth and the commands
// the controller writes: start and end (the controller's nav_state and goal on cmd_vel), success,
// the final goal error of the true pose, collisions, the smallest clearance of the body, danger-zone
// entries (any part of the footprint), door passages and those with a reversal of the driving
// direction inside the door region (oscillation), distance driven, and time against the
// wavefront-optimal path at full speed.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/sim/drive.hpp>
#include <polynav/zones.hpp>

#include <nlohmann/json.hpp>

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::engines {

struct MissionResult {
  std::string goal;
  bool started = false, ended = false, reached = false;
  bool settling = false;                  // the controller said reached/failed; the base is still braking
  std::string end_status;                 // the controller's status line at the end
  double t_start = 0, t_end = 0;          // s of simulated time
  double goal_error_m = std::numeric_limits<double>::quiet_NaN(), goal_yaw_error_deg = std::numeric_limits<double>::quiet_NaN();
  std::vector<CollisionEvent> collisions;
  double min_clearance_m = std::numeric_limits<double>::infinity();
  size_t danger_entries = 0;
  size_t door_passages = 0, door_oscillations = 0;  // passages; those with a reversal inside
  double driven_m = 0;
  double optimal_m = std::numeric_limits<double>::quiet_NaN();  // wavefront path from the start to the goal
  double duration() const { return t_end - t_start; }
};

class MissionTracker {
 public:
  using OptimalLength = std::function<double(const Eigen::Vector2d& from, const polynav::GoalSpot& goal)>;
  MissionTracker(const polynav::Zones& zones, std::vector<polynav::GoalSpot> goals, polynav::Polygon footprint,
                 OptimalLength optimal);
  // A command read from cmd_vel (goal, nav_state, status), at simulated time t, the robot truly at `truth`.
  void onCommand(uint32_t goal, uint32_t state, const std::string& status, double t, const Pose& truth);
  // Every simulator step: the true pose, the base's speeds, the body's clearance (m; +inf: not
  // measured). A mission the controller ended is scored here, once the base stands: the goal
  // error is where the robot came to rest, not where it was when the command was read.
  void onStep(const Pose& truth, double forward_speed, double turn_rate, double clearance);
  void onCollision(const CollisionEvent& c);
  // The current mission ends as failed (timeout of the evaluation, controller gone).
  void abort(double t, const std::string& why);
  bool done() const;
  bool settling() const { return current_ < results_.size() && results_[current_].settling; }
  size_t current() const { return current_; }
  const std::vector<MissionResult>& results() const { return results_; }
  nlohmann::json json() const;

 private:
  MissionResult* active();
  void settle(MissionResult& m, const Pose& truth);  // final: goal error from where it stands

  const polynav::Zones& zones_;
  std::vector<polynav::GoalSpot> goals_;
  polynav::Polygon footprint_;
  OptimalLength optimal_;
  std::vector<MissionResult> results_;
  size_t current_ = 0;
  std::optional<Pose> last_;
  bool in_danger_ = false;
  std::optional<size_t> door_;
  int door_sign_ = 0, door_reversals_ = 0;
};

}  // namespace polyloc::engines
