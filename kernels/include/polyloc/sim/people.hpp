// People walking through a simulation: scripted paths (waypoints at a walking speed, once or in
// a loop) or circles (around a fixed point or around the robot), each person a set of oriented
// boxes (legs, torso, head, two arms) with legs and arms swinging with the gait, about 0.5 m wide,
// 0.3 m deep and 1.75 m tall. Rays are intersected with the boxes analytically: people move every
// frame, and a few dozen boxes need no acceleration structure.
#pragma once

#include <polyloc/geometry/pose.hpp>

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

namespace polyloc {

struct PersonSpec {
  std::string name;
  std::vector<Eigen::Vector2d> waypoints;  // map frame; a path walked at `speed`
  bool loop = true;                        // walk back to the first waypoint and repeat
  bool circle = false;                     // walk a circle instead of waypoints
  bool around_robot = false;               // circle centre follows the robot
  Eigen::Vector2d centre{0, 0};            // circle centre (map) unless around_robot
  double radius = 1.5;                     // m, circle radius
  double speed = 1.2;                      // m/s walking speed (negative: clockwise circle)
  double start = 0.0;                      // s: appears at this time (after the run start)
  double end = std::numeric_limits<double>::infinity();  // s: leaves the scene
  double offset = 0.0;                     // m along the path (or arc) at `start`
  double z = 0.0;                          // m, floor height the person walks on
  double height = 1.75;                    // m; the body scales with it
};

struct PersonState {
  bool present = false;
  double x = 0, y = 0, z = 0, yaw = 0;
  double vx = 0, vy = 0;
  double phase = 0;  // gait phase (rad); 2 pi per 1.4 m stride cycle
};

// One oriented box: map_T_box rotation and centre, half extents.
struct OrientedBox {
  Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f half = Eigen::Vector3f::Zero();
};

// The boxes of everyone present at one time, with a bounding box per person for quick rejection.
struct PeopleScene {
  std::vector<OrientedBox> boxes;
  std::vector<Eigen::AlignedBox3f> bounds;      // per person
  std::vector<std::pair<size_t, size_t>> ranges;  // per person: [first, last) in boxes
  // Nearest hit along o + t d for t in [tmin, tmax]; returns +inf for none, else t and the unit
  // normal of the face hit (map frame). A ray starting inside a box hits it at tmin.
  float intersect(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tmin, float tmax,
                  Eigen::Vector3f* normal) const;
  bool empty() const { return boxes.empty(); }
};

class People {
 public:
  explicit People(std::vector<PersonSpec> specs);
  size_t size() const { return specs_.size(); }
  const PersonSpec& spec(size_t i) const { return specs_[i]; }
  // State of person i at time t (s since the run start); `robot` is the robot's (x, y) at t.
  PersonState state(size_t i, double t, const Eigen::Vector2d& robot) const;
  PeopleScene scene(double t, const Eigen::Vector2d& robot) const;
  // Closed loop (sim/drive.hpp): seconds each person has stood waiting for the robot so far; they
  // are that much behind on their way from then on (appearing and leaving keep their times).
  void setDelays(std::vector<double> delays) { delays_ = std::move(delays); }
  const std::vector<double>& delays() const { return delays_; }
  // Body boxes of one person (also used for plots and tests).
  static void addBody(const PersonState& s, double height, std::vector<OrientedBox>& out);

 private:
  std::vector<PersonSpec> specs_;
  std::vector<std::vector<double>> cum_;  // cumulative length at each waypoint (closed if loop)
  std::vector<double> delays_;            // per person, s (empty: none)
};

}  // namespace polyloc
