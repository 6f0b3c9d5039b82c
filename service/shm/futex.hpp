// The futex calls the channels wake and wait with. The words live in a MAP_SHARED segment
// mapped by several processes, so the operations are the shared ones (no FUTEX_PRIVATE_FLAG).
#pragma once

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdint>
#include <ctime>

namespace polyloc::shm::futex {

// Sleeps while *word == expected, at most timeout_ns (< 0: no limit). Returns false on timeout,
// true otherwise (woken, the word differed already, or a signal): callers re-check their
// condition, so a spurious true is harmless.
inline bool wait(const uint32_t* word, uint32_t expected, int64_t timeout_ns) {
  timespec ts{}, *tp = nullptr;
  if (timeout_ns >= 0) {
    ts.tv_sec = static_cast<time_t>(timeout_ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(timeout_ns % 1'000'000'000);
    tp = &ts;
  }
  const long r = syscall(SYS_futex, const_cast<uint32_t*>(word), FUTEX_WAIT, expected, tp, nullptr, 0);
  return !(r == -1 && errno == ETIMEDOUT);
}

// Wakes every process and thread sleeping on the word.
inline void wakeAll(uint32_t* word) { syscall(SYS_futex, word, FUTEX_WAKE, INT_MAX, nullptr, nullptr, 0); }

}  // namespace polyloc::shm::futex
