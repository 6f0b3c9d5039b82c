// polylocd's `clock: source` (SourceClock): no single frame sets the time; a time the inputs agree
// on moves the clock, forward or back.
#include "pipeline/source_clock.hpp"

#include <gtest/gtest.h>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_source_clock {

using namespace polyloc::pipeline;
using V = SourceClock::Verdict;

constexpr int64_t kMs = 1'000'000, kS = 1'000'000'000;
constexpr int64_t kT0 = 1'700'000'000 * kS;

// Takes frames of inputs 0 and 1, 10 ms apart, from `from`; returns the next stamp.
int64_t feed(SourceClock& c, int64_t from, int n, int64_t last[2]) {
  for (int k = 0; k < n; ++k, from += 10 * kMs) {
    c.beginPass();
    const size_t i = size_t(k % 2);
    EXPECT_EQ(c.judge(i, from, last[i]), V::Take) << k;
    c.taken(from);
    last[i] = from;
  }
  return from;
}

TEST(SourceClock, OneFarFutureStampIsRefusedAndChangesNothing) {
  SourceClock c(500 * kMs, 2 * kS, 5);
  int64_t last[2] = {0, 0};
  int64_t t = feed(c, kT0, 10, last);
  c.beginPass();
  EXPECT_EQ(c.judge(0, t + 1'000'000'000'000'000'000, last[0]), V::Future);
  EXPECT_FALSE(c.refused(0, t + 1'000'000'000'000'000'000));
  EXPECT_EQ(c.now(), t - 10 * kMs);  // still the newest good stamp
  t = feed(c, t, 10, last);          // every good frame after it is taken
  EXPECT_EQ(c.jumps(), 0u);
  // Stale: older than the clock by more than max_age.
  c.beginPass();
  EXPECT_EQ(c.judge(1, t - 2 * kS, 0), V::Stale);
}

TEST(SourceClock, ACorruptFirstFrameIsOutvoted) {
  SourceClock c(500 * kMs, 2 * kS, 5);
  c.beginPass();
  const int64_t corrupt = kT0 + 1'000'000'000'000'000'000;  // 1e18 ns (31 years) ahead
  EXPECT_EQ(c.judge(0, corrupt, 0), V::Take);  // nothing to judge the first by
  c.taken(corrupt);
  int64_t t = kT0;
  bool jumped = false;
  int refused = 0;
  for (int k = 0; k < 20 && !jumped; ++k, t += 10 * kMs) {
    c.beginPass();
    const V v = c.judge(size_t(k % 2), t, 0);
    ASSERT_EQ(v, V::Stale);
    ++refused;
    jumped = c.refused(size_t(k % 2), t);
  }
  EXPECT_TRUE(jumped);
  EXPECT_EQ(refused, 5);
  EXPECT_EQ(c.now(), t - 10 * kMs);
  c.beginPass();
  EXPECT_EQ(c.judge(0, t, 0), V::Take);
}

TEST(SourceClock, AJumpOfEveryInputMovesTheClockForwardAndBack) {
  for (const int64_t jump : {3600 * kS, -3600 * kS}) {
    SourceClock c(500 * kMs, 2 * kS, 5);
    int64_t last[2] = {0, 0};
    int64_t t = feed(c, kT0, 10, last) + jump;
    int refused = 0;
    for (;; t += 10 * kMs) {
      c.beginPass();
      const size_t i = size_t(refused % 2);
      ASSERT_EQ(c.judge(i, t, last[i]), jump > 0 ? V::Future : V::Stale);
      ++refused;
      if (c.refused(i, t)) break;
      ASSERT_LT(refused, 5);
    }
    EXPECT_EQ(refused, 5);
    EXPECT_EQ(c.now(), t);
    EXPECT_EQ(c.jumps(), 1u);
  }
}

TEST(SourceClock, OneInputAloneCannotOutvoteTheOthers) {
  SourceClock c(500 * kMs, 2 * kS, 5);
  int64_t last[2] = {0, 0};
  const int64_t t = feed(c, kT0, 10, last);
  // Input 1 floods agreeing far-future stamps while input 0 is quiet: never a jump.
  for (int k = 0; k < 1000; ++k) {
    c.beginPass();
    ASSERT_EQ(c.judge(1, t + 3600 * kS + k, last[1]), V::Future);
    ASSERT_FALSE(c.refused(1, t + 3600 * kS + k));
  }
  EXPECT_EQ(c.jumps(), 0u);
  c.beginPass();
  EXPECT_EQ(c.judge(0, t, last[0]), V::Take);
}

TEST(SourceClock, TheOnlyInputThatSendsMovesItAlone) {
  SourceClock c(500 * kMs, 2 * kS, 3);
  c.beginPass();
  ASSERT_EQ(c.judge(0, kT0, 0), V::Take);
  c.taken(kT0);
  bool jumped = false;
  for (int k = 0; k < 3; ++k) {
    c.beginPass();
    ASSERT_EQ(c.judge(0, kT0 + 60 * kS + k * 10 * kMs, kT0), V::Future);
    jumped = c.refused(0, kT0 + 60 * kS + k * 10 * kMs);
  }
  EXPECT_TRUE(jumped);
}

TEST(SourceClock, ABacklogOfOneInputIsNotFuture) {
  // One pass reads 5 s of input 0 before input 1's frames: each frame is judged against its own
  // previous one and the clock at the start of the pass.
  SourceClock c(500 * kMs, 2 * kS, 5);
  int64_t last[2] = {0, 0};
  int64_t t = feed(c, kT0, 4, last);
  c.beginPass();
  for (int64_t s = t; s < t + 5 * kS; s += 100 * kMs) {
    ASSERT_EQ(c.judge(0, s, last[0]), V::Take);
    c.taken(s);
    last[0] = s;
  }
  EXPECT_EQ(c.judge(1, t + 5 * kMs, last[1]), V::Take);  // not stale against input 0's newest
}

TEST(SourceClock, AFrameSentAThousandTimesIsARepeatNotAVote) {
  SourceClock c(500 * kMs, 2 * kS, 5);
  c.beginPass();
  ASSERT_EQ(c.judge(0, kT0, 0), V::Take);
  c.taken(kT0);
  for (int k = 0; k < 1000; ++k) {
    c.beginPass();
    ASSERT_EQ(c.judge(0, kT0, kT0), V::Repeat);
  }
  // An old frame resent (older than max_age, so Stale): the same stamp again is no advancing clock.
  for (int k = 0; k < 1000; ++k) {
    c.beginPass();
    ASSERT_EQ(c.judge(0, kT0 - 60 * kS, kT0), V::Stale);
    ASSERT_FALSE(c.refused(0, kT0 - 60 * kS));
  }
  EXPECT_EQ(c.jumps(), 0u);
}

}  // namespace polyloc::t_source_clock
