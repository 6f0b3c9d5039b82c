// `polylocd.clock: source` (docs/failure.md, "Time"): time is what the inputs' stamps say, not
// CLOCK_REALTIME, so a recording replays at any rate. No single frame may set that time: a stamp
// more than max_future after both the clock and its own input's last stamp is refused (future), one
// more than max_age before the clock is refused (stale), and the clock moves to another time only
// when `agree` refused frames in a row agree on it (consecutive ones within max_future of each
// other) and come from two inputs, or from the only one that sends. That is a jump (a recording
// restarted, a clock set on the robot, or a first frame that was corrupt): the caller starts anew.
//
//   SourceClock c(max_age, max_future, 5);
//   c.beginPass();                         // one reference for a whole read pass (a backlog)
//   switch (c.judge(input, stamp, last))   // Take: c.taken(stamp); else if (c.refused(input, stamp)) restart
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace polyloc::pipeline {

class SourceClock {
 public:
  // Repeat: not after its input's last stamp but within max_age of the clock (a duplicate or a
  // reordered frame): refused, and never a vote for another time.
  enum class Verdict { Take, Stale, Future, Repeat };

  SourceClock(int64_t max_age_ns, int64_t max_future_ns, size_t agree);

  bool started() const { return now_ != kNone; }
  int64_t now() const { return now_; }  // the newest stamp taken; meaningless before started()
  uint64_t jumps() const { return jumps_; }

  // Fixes the reference of the pass that follows: a backlog read in one pass must not make the
  // slower channels' frames stale against the faster ones' newest stamps.
  void beginPass() { pass_now_ = now_; }
  // A stamp of `input`, whose last taken stamp is `last` (0: none). In the first pass every stamp
  // is taken (there is nothing to judge it against; a wrong one there is outvoted later).
  Verdict judge(size_t input, int64_t stamp, int64_t last);
  void taken(int64_t stamp);
  // A frame judge() found Stale or Future. True when the refused frames now agree on another time
  // (each input's stamps increasing): the clock is there (now()), and the caller must drop what it
  // holds of the old time.
  bool refused(size_t input, int64_t stamp);

 private:
  static constexpr int64_t kNone = INT64_MIN;
  int64_t max_age_, max_future_;
  size_t agree_;
  int64_t now_ = kNone, pass_now_ = kNone;
  uint64_t jumps_ = 0;
  std::vector<bool> seen_;  // inputs that sent a frame
  struct Refused {
    size_t input;
    int64_t stamp;
  };
  std::vector<Refused> streak_;  // refused frames in a row that agree with each other
};

}  // namespace polyloc::pipeline
