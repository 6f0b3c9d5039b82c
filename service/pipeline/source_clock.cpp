#include "pipeline/source_clock.hpp"

#include <algorithm>

namespace polyloc::pipeline {

namespace {
// a - b > limit, without overflow for any two stamps.
bool beyond(int64_t a, int64_t b, int64_t limit) { return static_cast<__int128>(a) - b > limit; }
}  // namespace

SourceClock::SourceClock(int64_t max_age_ns, int64_t max_future_ns, size_t agree)
    : max_age_(max_age_ns), max_future_(max_future_ns), agree_(std::max<size_t>(agree, 1)) {}

SourceClock::Verdict SourceClock::judge(size_t input, int64_t stamp, int64_t last) {
  if (input >= seen_.size()) seen_.resize(input + 1, false);
  seen_[input] = true;
  if (pass_now_ == kNone) return last != 0 && stamp <= last ? Verdict::Repeat : Verdict::Take;
  if (last != 0 && stamp <= last) return beyond(pass_now_, stamp, max_age_) ? Verdict::Stale : Verdict::Repeat;
  // Ahead of the clock and of its own last stamp: one frame period after its previous frame is
  // normal when this input's backlog is read before the others'.
  if (beyond(stamp, std::max(pass_now_, last), max_future_)) return Verdict::Future;
  if (beyond(pass_now_, stamp, max_age_)) return Verdict::Stale;
  return Verdict::Take;
}

void SourceClock::taken(int64_t stamp) {
  now_ = now_ == kNone ? stamp : std::max(now_, stamp);  // the first pass takes all: no reference yet
  streak_.clear();
}

bool SourceClock::refused(size_t input, int64_t stamp) {
  if (!streak_.empty() && (beyond(stamp, streak_.back().stamp, max_future_) || beyond(streak_.back().stamp, stamp, max_future_)))
    streak_.clear();  // disagrees with the streak: a new one starts with it
  for (const Refused& r : streak_)
    if (r.input == input && r.stamp >= stamp) {  // a clock that does not advance is no clock
      streak_.clear();
      break;
    }
  streak_.push_back({input, stamp});
  if (streak_.size() > 4 * agree_) streak_.erase(streak_.begin());  // bounded under a flood
  if (streak_.size() < agree_) return false;
  const size_t senders = size_t(std::count(seen_.begin(), seen_.end(), true));
  std::vector<size_t> inputs;
  for (const Refused& r : streak_) inputs.push_back(r.input);
  std::sort(inputs.begin(), inputs.end());
  const size_t distinct = size_t(std::unique(inputs.begin(), inputs.end()) - inputs.begin());
  if (distinct < std::min<size_t>(2, senders)) return false;  // one input alone outvotes no others
  int64_t newest = streak_.front().stamp;
  for (const Refused& r : streak_) newest = std::max(newest, r.stamp);
  now_ = pass_now_ = newest;
  streak_.clear();
  ++jumps_;
  return true;
}

}  // namespace polyloc::pipeline
