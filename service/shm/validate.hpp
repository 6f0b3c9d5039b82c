// The checks polylocd makes on every frame it reads from an input channel, before a kernel sees
// it: kind and size against the channel, counts, NaN/inf where a number is required, stamps too
// old or in the future. Pure functions over the bytes as read (also the libFuzzer target).
#pragma once

#include <polyloc_shm.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace polyloc::shm {

enum class Reject { None, Size, NaN, Stale, Future };
const char* toString(Reject r);  // "ok", "size", "nan", "stale", "future"

struct StampRules {
  int64_t now_ns = 0;          // CLOCK_REALTIME now
  int64_t last_ns = INT64_MIN; // stamp of the last frame taken on this channel
  int64_t max_age_ns = 500'000'000;     // older than now - max_age: stale (< 0: not checked)
  int64_t max_future_ns = 100'000'000;  // later than now + max_future: future (< 0: not checked)
};

struct Validation {
  Reject reject = Reject::None;
  std::string why;             // "scan/front frame 123: 540 bytes, expected 1096 for 270 beams"
  explicit operator bool() const { return reject == Reject::None; }
};

// payload/bytes: the frame as read from the slot (bytes = slot size field, not trusted).
// RANGES: count == channel count (any count when the channel's is 0), size exact; a frame whose
// ranges are all NaN or inf is Reject::NaN (single invalid beams are normal: no return). DEPTH: width/height == channel's, size exact
// for has_amplitude 0/1. ODOMETRY: size exact, pose finite, quaternion norm within 1e-3 of 1
// (a non-unit quaternion is Reject::NaN too: a number out of its domain). COMMAND: size exact,
// vx vy wz finite within +-100, nav_state 0..3, status NUL-terminated. A size field beyond
// the channel's payload_max is Reject::Size before any byte is read; only `bytes` bytes are
// read otherwise. Then the stamp rules on the payload's stamp_ns (a non-increasing stamp is Stale).
Validation validateInput(const polyloc_channel_desc& channel, uint64_t frame, const uint8_t* payload,
                         size_t bytes, const StampRules& rules);

// The domain of a velocity command, one rule for every writer (the C client, the Python
// bindings) and for the segment check: vx vy wz finite within +-POLYLOC_COMMAND_MAX, nav_state a
// POLYLOC_NAV_* value. "" when the command is in its domain, else what is wrong ("vx is nan: not
// within +-100", "nav_state 7, expected 0..3").
std::string commandProblem(double vx, double vy, double wz, uint32_t nav_state);

}  // namespace polyloc::shm
