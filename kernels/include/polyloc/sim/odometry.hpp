// Simulated wheel odometry: integrates the true motion between ticks with drift (OdometryNoise,
// in noise.hpp) into a planar pose in the odom frame, which starts at the robot's start pose
// (odom = base_link at t = 0). Random numbers are keyed by (seed, tick), so the same run gives
// the same drift on any thread count.
#pragma once

#include <polyloc/geometry/pose.hpp>
#include <polyloc/geometry/random.hpp>
#include <polyloc/sim/noise.hpp>

#include <array>

namespace polyloc {

class OdometrySimulator {
 public:
  OdometrySimulator(const OdometryNoise& noise, bool enabled, uint64_t seed);

  // Starts at the true pose of tick 0 (6-DoF; the planar part defines the odom frame).
  void reset(const Pose& map_T_base);
  // One tick: the robot moved to `map_T_base` during `dt` seconds.
  void step(const Pose& map_T_base, double dt);

  const Pose& pose() const { return odom_T_base_; }  // planar: z = roll = pitch = 0
  // Velocity in base_link from the last step: vx, vy (m/s), wz (rad/s).
  const Eigen::Vector3d& twist() const { return twist_; }
  // Accumulated variances (x, y, yaw) of the drift, for the message covariance.
  const Eigen::Vector3d& variance() const { return var_; }
  uint64_t ticks() const { return tick_; }

 private:
  OdometryNoise noise_;
  bool enabled_;
  CounterRng rng_;
  Pose prev_;  // previous true pose (map)
  Pose odom_T_base_;
  Eigen::Vector3d twist_ = Eigen::Vector3d::Zero(), var_ = Eigen::Vector3d::Zero();
  double x_ = 0, y_ = 0, yaw_ = 0;
  uint64_t tick_ = 0;
};

}  // namespace polyloc
