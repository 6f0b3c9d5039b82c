// Restamping a recording by message order: message i (in file order) gets the stamp
// start + i / rate_hz, in its log time and in its header (and a TFMessage's transforms). For logs
// whose stamps cannot be used (written with too few digits, all zero, going backwards: see
// io/stamp_check.hpp): the order of messages is what they still tell, and the localiser needs
// only that (odometry interpolated between the neighbours of each scan). `--restamp HZ` of
// `polyloc info`, `localize` and `relocalize` wraps the reader in this.
#pragma once

#include <polyloc/io/recording.hpp>

#include <cmath>
#include <cstdint>
#include <memory>

namespace polyloc {

inline constexpr int64_t kRestampStartNs = 1'000'000'000;  // the first message's stamp: 1 s

// The stamp of the message at `index` in the recording, restamped at rate_hz.
inline int64_t restampedNs(uint64_t index, double rate_hz) {
  return kRestampStartNs + int64_t(std::llround(double(index) * 1e9 / rate_hz));
}

// Throws std::invalid_argument for a rate that is not finite and positive (or above 1 GHz).
std::unique_ptr<RecordingReader> restampByOrder(std::unique_ptr<RecordingReader> reader, double rate_hz);

// The message with every stamp it carries set to t.
void setStamps(msg::Message& m, int64_t t_ns);

}  // namespace polyloc
