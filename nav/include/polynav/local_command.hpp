// What a local obstacle avoidance method (nearness_diagram.hpp, vfh.hpp) answers, and the motion
// law they share: a direction of motion in the base frame becomes (v, w) for a differential base.
// The speed drops with the heading error and is 0 beyond 90 degrees, so the robot turns in place
// towards a direction behind it instead of driving an arc away from it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace polynav {

// The robot's limits that scale the command (named after ND, the thesis's method; VFH uses them too).
struct NdLimits {
  double max_speed = 0.5;     // m/s
  double max_yaw_rate = 1.0;  // rad/s

  // Throws std::invalid_argument, prefixed with `who`, naming a limit that is negative or not finite.
  void validate(const std::string& who) const {
    std::ostringstream s;
    if (!(max_speed >= 0) || !std::isfinite(max_speed)) s << "max_speed must be finite and >= 0, got " << max_speed;
    else if (!(max_yaw_rate >= 0) || !std::isfinite(max_yaw_rate))
      s << "max_yaw_rate must be finite and >= 0, got " << max_yaw_rate;
    if (!s.str().empty()) throw std::invalid_argument(who + ": NdLimits: " + s.str());
  }
};

struct LocalCommand {
  double v = 0, w = 0;    // m/s forward, rad/s counter-clockwise
  double direction = 0;   // rad, base frame, (-pi, pi]: the chosen direction of motion
  // m, the smallest gap between the hull and anything the scan saw (0 for a point inside the
  // hull, +inf when nothing was seen)
  double min_clearance = std::numeric_limits<double>::infinity();
  bool blocked = false;   // no way towards the goal: v = w = 0, a case for the global planner
};

// The shared motion law: v = max_speed x speed_scale (clamped to [0, 1]) x max(0, cos(error)),
// w = max_yaw_rate x error / (pi / 2) clamped to +-max_yaw_rate, where the heading error is the
// direction itself (the robot heads along x).
inline LocalCommand steer(double direction, double speed_scale, const NdLimits& limits) {
  LocalCommand c;
  c.direction = std::remainder(direction, 2 * M_PI);
  const double error = c.direction;
  c.v = limits.max_speed * std::clamp(speed_scale, 0.0, 1.0) * std::max(0.0, std::cos(error));
  c.w = std::clamp(limits.max_yaw_rate * error / (M_PI / 2), -limits.max_yaw_rate, limits.max_yaw_rate);
  return c;
}

}  // namespace polynav
