#include <polyloc/mcl/round.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc {

namespace {
constexpr int64_t kSilentNs = 1'000'000'000;  // a sensor not heard from for this long is not waited for
}  // namespace

UpdateRound::UpdateRound(const MclConfig& config, std::vector<uint8_t> weighed)
    : round_timeout_(config.round_timeout), update_min_distance_(config.update_min_distance),
      update_min_angle_(config.update_min_angle), weighed_(std::move(weighed)) {
  pending_.assign(weighed_.size(), 0);
  frames_.resize(weighed_.size());
  last_scan_.assign(weighed_.size(), std::numeric_limits<int64_t>::min());
}

bool UpdateRound::open() const { return std::count(pending_.begin(), pending_.end(), uint8_t{1}) > 0; }

// A round still open after round_timeout (a sensor dropped out) is closed with what it has.
bool UpdateRound::timedOut(int64_t stamp) const {
  return open() && stamp - start_ > int64_t(round_timeout_ * 1e9);
}

// A round starts after enough motion (or with the first scan); every sensor then contributes
// its next frame. Motion during an open round does not restart it (a turn in place would then
// close every round after one or two sensors, and resample on their evidence alone).
bool UpdateRound::due(const Pose& moved) const {
  const double turned = std::abs(Eigen::AngleAxisd(moved.rotation()).angle());
  return !open() && (!started_once_ || moved.translation().norm() >= update_min_distance_ ||
                     turned >= update_min_angle_);
}

void UpdateRound::start(size_t sensor, int64_t stamp) {
  // Waits for the sensors heard from lately: one that is silent (dropped out, or not recorded)
  // would hold every round open until round_timeout.
  for (size_t k = 0; k < pending_.size(); ++k)
    pending_[k] = weighed_[k] != 0 && (k == sensor || last_scan_[k] > stamp - kSilentNs);
  start_ = stamp;
  started_once_ = true;
}

bool UpdateRound::take(size_t sensor) {
  if (!pending_[sensor]) return false;
  pending_[sensor] = 0;
  return true;
}

bool UpdateRound::complete() const { return std::count(pending_.begin(), pending_.end(), uint8_t{1}) == 0; }

void UpdateRound::abandon() { std::fill(pending_.begin(), pending_.end(), 0); }

void UpdateRound::reset() {
  std::fill(pending_.begin(), pending_.end(), 0);
  started_once_ = false;
  sensors = lost = collapsed = 0;
  inject_due = 0;
}

void UpdateRound::keep(size_t sensor, std::span<const float> ranges, const Pose& odom) {
  RoundFrame& f = frames_[sensor];
  f.ranges.assign(ranges.begin(), ranges.end());
  f.odom = odom;
  f.valid = true;
}

std::vector<RefineScan> UpdateRound::scans(const Pose& ref) const {
  std::vector<RefineScan> scans;
  for (size_t k = 0; k < frames_.size(); ++k)
    if (frames_[k].valid) scans.push_back(RefineScan{k, frames_[k].ranges, ref.inverse() * frames_[k].odom});
  return scans;
}

void UpdateRound::clear() {
  sensors = lost = collapsed = 0;
  inject_due = 0;
  for (RoundFrame& f : frames_) f.valid = false;  // the data stays until the next round overwrites it
}

}  // namespace polyloc
