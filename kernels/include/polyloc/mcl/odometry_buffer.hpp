// The odometry the filter has heard: the last kOdomHistoryNs of cumulative odom_T_base poses,
// and the odometry at any stamp (interpolated, or extrapolated a little past the last message).
#pragma once

#include <polyloc/geometry/pose.hpp>

#include <cstdint>
#include <deque>
#include <utility>

namespace polyloc {

class OdometryBuffer {
 public:
  // What add() did with a message, for the counters.
  enum class Added {
    First,       // accepted, the first one: the reference, no motion before it
    Accepted,
    AfterGap,    // accepted after a silence of more than kOdometryGapNs: still used, the delta spans the gap
    Invalid,     // non-finite, or beyond the domain (geometry/domain.hpp): ignored
    OutOfOrder,  // older than the last one: ignored
  };
  Added add(int64_t stamp, const Pose& odom_T_base);

  // Odometry at time t: scans and odometry come at different rates, and a scanner at 12.5 Hz
  // lags 50 Hz odometry by up to 20 ms, a degree at 0.8 rad/s. A scan newer than the last
  // odometry (it arrived first) gets the last motion extrapolated, for at most kExtrapolateNs.
  // Identity before any odometry.
  Pose at(int64_t t) const;

 private:
  bool have_ = false;
  int64_t last_t_ = 0;
  Pose last_;
  std::deque<std::pair<int64_t, Pose>> history_;  // the last kOdomHistoryNs of odometry
};

}  // namespace polyloc
