// Speed along a path: the fastest profile that starts and ends at rest and respects a speed
// limit per point (max speed, curvature and yaw-rate limits) and a maximum acceleration. Built on
// a grid of arc length with v^2 linear in s between grid points, i.e. constant acceleration
// within each cell, so the limits hold exactly between samples too (forward/backward pass).
#pragma once

#include <functional>
#include <vector>

namespace polyloc {

struct SpeedLimits {
  double max_speed = 0.5;         // m/s
  double max_acceleration = 0.5;  // m/s^2, also braking
};

class SpeedProfile {
 public:
  // `limit(s)` caps the speed at arc length s (return +inf for no extra cap). ds: grid step.
  // `kinks`: arc lengths where limit(s) may have a corner (spline knots: the curvature is only
  // continuous there); the limit is sampled there too, so it holds between grid points.
  SpeedProfile(double length, const SpeedLimits& limits,
               const std::function<double(double)>& limit = {}, double ds = 0.01,
               const std::vector<double>& kinks = {});

  double length() const { return length_; }
  double duration() const { return time_.back(); }
  // At time tau since the start (clamped to [0, duration]): arc length, speed, acceleration.
  struct State {
    double s = 0, v = 0, a = 0;
  };
  State at(double tau) const;
  double speedAt(double s) const;  // grid speed, linear in v^2

 private:
  double length_, ds_;
  std::vector<double> v_, time_;  // per grid point
};

}  // namespace polyloc
