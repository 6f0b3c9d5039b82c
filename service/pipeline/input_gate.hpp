// polylocd's inputs up to the pipeline: every input channel read dry in one pass, each frame
// checked (shm::validateInput) and its stamp judged (the wall clock, or SourceClock under
// `clock: source`), what is refused counted per input and reason and logged (rate-limited),
// what is taken put in order (stamp order; each sensor frame after the odometry that covers its
// stamp, waiting for it at most odom_wait) and handed over. The daemon runs the pipeline and
// publishes; this decides what the pipeline gets, and when. Health per input lives here.
//
//   InputGate gate(seg, table, cfg, [&](int64_t from, int64_t to) { restart(); });
//   if (gate.read()) for (const auto& f : gate.ready()) dispatch(f);
#pragma once

#include "pipeline/channels.hpp"
#include "pipeline/daemon_config.hpp"
#include "pipeline/source_clock.hpp"
#include "shm/channel.hpp"
#include "shm/validate.hpp"

#include <ctime>
#include <functional>
#include <vector>

namespace polyloc::pipeline {

int64_t clockNs(clockid_t clock);  // clock_gettime in ns
inline int64_t monotonicNs() { return clockNs(CLOCK_MONOTONIC); }

class InputGate {
 public:
  // A frame taken, as read.
  struct Frame {
    int64_t stamp_ns = 0, publish_ns = 0;
    int64_t read_mono = 0;  // CLOCK_MONOTONIC when read (odom_wait)
    int input = 0;          // position in ChannelTable::inputs
    std::vector<uint8_t> payload;
  };
  // clock: source moved to another time (from, to): what was held of the old time is gone here;
  // the caller starts its own state again.
  using TimeJump = std::function<void(int64_t from, int64_t to)>;

  InputGate(shm::Segment& seg, const ChannelTable& table, const DaemonConfig& cfg, TimeJump on_jump);

  // Reads every input channel dry; true when something was read. ready() then holds the frames
  // to dispatch now, in order (frames waiting for their odometry are kept for a later call).
  bool read();
  const std::vector<Frame>& ready() const { return ready_; }
  // The time frames are judged against: CLOCK_REALTIME, or the source clock once it started.
  int64_t now() const;
  // How long the caller may sleep: until the first waiting frame's wait ends, at most 20 ms.
  int64_t sleepNs(int64_t mono) const;

  // A frame the pipeline refused after the gate took it (a size it cannot use).
  void dispatched(int input, bool ok) { ok ? ++health_[size_t(input)].taken : ++health_[size_t(input)].rejected_size; }
  // Renews each input's silent flag (no frame for input_timeout), logging changes; the health
  // per input, in ChannelTable::inputs order.
  const std::vector<polyloc_input_health>& health(int64_t mono);

 private:
  const polyloc_channel_desc& desc(size_t input) const;
  void reject(size_t input, const shm::Validation& v);
  bool admit(size_t input, int64_t stamp);
  void order(std::vector<Frame>& pass);
  void schedule(int64_t mono);

  shm::Segment& seg_;
  const ChannelTable& table_;
  const DaemonConfig& cfg_;
  TimeJump on_jump_;
  std::vector<shm::Reader> readers_;  // per input, in ChannelTable::inputs order
  std::vector<polyloc_input_health> health_;
  std::vector<int64_t> last_taken_mono_;  // per input: CLOCK_MONOTONIC of the last frame taken (0: none)
  std::vector<bool> announced_;           // per input: its first frames were logged
  std::vector<uint64_t> logged_;          // per input: rejections logged (rate limit)
  int odom_input_ = -1;                   // the odometry channel's position in inputs; -1: none
  SourceClock clock_;
  std::vector<Frame> ready_, held_;       // held: sensor frames waiting for the odometry that covers them
};

}  // namespace polyloc::pipeline
