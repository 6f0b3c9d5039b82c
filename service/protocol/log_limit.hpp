// Rate limit for log lines that a client can provoke (garbage, bad CRCs, slow readers): at most
// `burst` lines per kind and window, then silence until the window ends; the next line says how
// many were suppressed. A misbehaving client must not be able to flood the daemon's log.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>

namespace polyloc::protocol {

class LogLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  explicit LogLimiter(int burst = 5, Clock::duration window = std::chrono::seconds(10))
      : burst_(burst), window_(window) {}

  // True: log this line (after `suppressed` lines of this kind were dropped since the last one).
  bool allow(const std::string& kind, uint64_t& suppressed, Clock::time_point now = Clock::now()) {
    Slot& s = slots_[kind];
    if (now - s.start >= window_) s.start = now, s.used = 0;
    if (s.used < burst_) {
      ++s.used;
      suppressed = s.dropped;
      s.dropped = 0;
      return true;
    }
    ++s.dropped;
    return false;
  }

 private:
  struct Slot {
    Clock::time_point start{};
    int used = 0;
    uint64_t dropped = 0;
  };
  int burst_;
  Clock::duration window_;
  std::map<std::string, Slot> slots_;
};

}  // namespace polyloc::protocol
