#include <polyloc/geometry/domain.hpp>
#include <polyloc/mcl/odometry_buffer.hpp>

#include <algorithm>

namespace polyloc {

namespace {
constexpr int64_t kOdometryGapNs = 1'000'000'000;
constexpr int64_t kOdomHistoryNs = 2'000'000'000;  // odometry kept for interpolation to scan stamps
constexpr int64_t kExtrapolateNs = 100'000'000;
}  // namespace

OdometryBuffer::Added OdometryBuffer::add(int64_t stamp, const Pose& odom_T_base) {
  if (domain::checkPose(odom_T_base)) return Added::Invalid;
  if (have_ && stamp < last_t_) return Added::OutOfOrder;
  Added added = Added::Accepted;
  if (!have_) {
    have_ = true;
    added = Added::First;
  } else if (stamp - last_t_ > kOdometryGapNs) {
    added = Added::AfterGap;
  }
  last_t_ = stamp;
  last_ = odom_T_base;
  history_.emplace_back(stamp, odom_T_base);
  while (history_.size() > 2 && stamp - history_.front().first > kOdomHistoryNs) history_.pop_front();
  return added;
}

Pose OdometryBuffer::at(int64_t t) const {
  if (history_.size() >= 2 && t > history_.back().first) {
    const auto& [t1, p1] = history_.back();
    const auto& [t0, p0] = history_[history_.size() - 2];
    if (t - t1 > kExtrapolateNs || t1 <= t0) return last_;
    return Pose::interpolate(p0, p1, 1.0 + double(t - t1) / double(t1 - t0));
  }
  if (history_.empty() || t >= history_.back().first) return last_;
  if (t <= history_.front().first) return history_.front().second;
  auto hi = std::lower_bound(history_.begin(), history_.end(), t,
                             [](const auto& e, int64_t v) { return e.first < v; });
  auto lo = hi - 1;
  const double s = double(t - lo->first) / double(hi->first - lo->first);
  return Pose::interpolate(lo->second, hi->second, s);
}

}  // namespace polyloc
