// Following a planned path: where the robot is along it (the nearest point, searched forward
// from the last one, so a path that passes a place twice is followed in order), the carrot a
// look-ahead distance further on, and how much the path turns ahead (curve regions: slow down
// and keep the orientation tangential).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace polynav {

class PathFollow {
 public:
  PathFollow() = default;
  explicit PathFollow(std::vector<Eigen::Vector2d> path);

  bool empty() const { return path_.size() < 2; }
  const std::vector<Eigen::Vector2d>& path() const { return path_; }
  // Moves the progress to the point of the path nearest `p`, searching `window_m` metres ahead
  // of the current progress (never backwards). Returns the distance from p to the path.
  double update(const Eigen::Vector2d& p, double window_m = 2.0);
  // The point `ahead_m` along the path from the progress point (the end when beyond it).
  Eigen::Vector2d carrot(double ahead_m) const;
  // Unit direction of the path at `ahead_m` from the progress point.
  Eigen::Vector2d direction(double ahead_m = 0) const;
  // The largest change of direction (rad, >= 0) between the progress point and ahead_m further.
  double turnAhead(double ahead_m) const;
  double remaining() const;   // m from the progress point to the end
  double travelled() const { return s_; }  // arc length of the progress point
  size_t segment() const { return seg_; }  // the progress point lies on segment [seg, seg + 1]

 private:
  Eigen::Vector2d at(double s) const;  // the point at arc length s (clamped)

  std::vector<Eigen::Vector2d> path_;
  std::vector<double> cum_;  // arc length at each vertex
  size_t seg_ = 0;
  double s_ = 0;
};

}  // namespace polynav
