// Writing and reading one channel of a segment (seqlock slots, see service/shm/include/polyloc_shm.h).
// A writer never waits for readers; any number of readers read in place at their own speed.
//
//   shm::Writer w(seg, seg.find("scan/front"));          // claims the writer role
//   auto* p = w.begin();  ...fill p (payload_max bytes)...;  w.commit(bytes, stamp_ns);
//
//   shm::Reader r(seg, seg.find("pose"));                 // starts after the newest frame
//   while (r.wait(100'000'000)) while (auto f = r.next(buf)) use(*f, buf);
//
// Both keep a pointer to the Segment object: after `seg = Segment::attach(...)` (re-attach) they
// follow the new mapping on their next call (the channel found again by name; a reader of a new
// generation starts at its oldest frame; ShmError when the channel is gone).
#pragma once

#include "shm/segment.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::shm {

class Writer {
 public:
  // Claims the channel's writer role: throws ShmError when a live process other than this one
  // holds it, unless take_over (a dead holder is always replaced, and counted in writer_claims).
  Writer(Segment& seg, int channel, bool take_over = false);
  ~Writer();  // releases the role
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // The payload area of the next frame's slot (seq set odd): payload_max bytes. Throws ShmError
  // when another process has taken the role over meanwhile.
  uint8_t* begin();
  // Completes the frame begun: seq even, write_count + 1, futex wake. bytes <= payload_max.
  // Input channels also ring the segment's doorbell.
  void commit(uint32_t bytes, int64_t stamp_ns);
  // begin + memcpy + commit. Throws std::length_error when bytes > payload_max.
  void write(const void* payload, uint32_t bytes, int64_t stamp_ns);
  uint64_t written() const;   // frames committed on the channel
  const polyloc_channel_desc& channel() const;

 private:
  void bind();
  void claim(bool take_over);
  Segment* seg_;
  int ch_;
  std::string name_;
  uint8_t* base_ = nullptr;   // the mapping bound to (changes on re-attach)
  polyloc_ring_control* ring_ = nullptr;
  polyloc_slot_header* slot_ = nullptr;   // of the frame begun
  int32_t pid_ = 0;           // this process, as claimed (a Writer does not cross a fork)
  uint64_t frame_ = 0;
  bool open_ = false;
};

struct FrameInfo {
  uint64_t frame = 0;       // its number on the channel
  uint32_t size = 0;        // payload bytes as the writer set them (untrusted: at most payload_max are readable)
  uint32_t kind = 0;
  int64_t stamp_ns = 0, publish_ns = 0;
};

// How long Reader::wait spins (checking write_count) before it sleeps in FUTEX_WAIT. Spinning
// catches a frame that comes within that time without the wake-up of a sleeping thread (the
// cost that dominates latency); it burns the CPU meanwhile. docs/interface.md, "Waiting", has
// the measurements behind the default.
inline constexpr int64_t kDefaultSpinNs = 0;

class Reader {
 public:
  enum class Start { Newest, Oldest, Next };  // Newest: the last published frame is read first; Next: only frames after attaching
  Reader(const Segment& seg, int channel, Start start = Start::Next);

  // The next unread frame copied into `payload` (resized); nullopt when none is new. After an
  // overrun (the writer lapped this reader) skips to the newest frame and counts it.
  std::optional<FrameInfo> next(std::vector<uint8_t>& payload);
  // The newest complete frame (skips everything older, read or not: no overrun), copied; nullopt
  // when none was ever published.
  std::optional<FrameInfo> newest(std::vector<uint8_t>& payload);
  // In place: f(const FrameInfo&, const uint8_t* payload) is called on the slot memory, then the
  // slot's seq is re-checked; returns false (and f's work must be discarded) when the frame was
  // overwritten while f ran. Advances like next(). Also false (f not called) when none is new.
  template <class F> bool readInPlace(F&& f);

  // Blocks until a frame newer than the last read is published or timeout (ns; FUTEX_WAIT on the
  // ring's notify word); true when one is there. timeout 0: poll. Spins up to spin_ns first.
  bool wait(int64_t timeout_ns, int64_t spin_ns = kDefaultSpinNs);
  uint64_t available() const;   // published frames not yet read (capped at slot_count)
  uint64_t overruns() const;    // frames lost to overruns
  uint64_t torn() const;        // reads retried because the writer overwrote the slot meanwhile
  const polyloc_channel_desc& channel() const;

 private:
  void bind(Start start) const;
  void rebindIfMoved() const;   // follows a re-attach (the state below is mutable for that)
  // The slot of the next frame to read and its seq (frame complete), or nullptr when none is new.
  const polyloc_slot_header* locate(FrameInfo& info, uint64_t& seq);
  // After reading the slot: true (and advance) when its seq is still the one locate saw.
  bool confirm(const polyloc_slot_header* slot, uint64_t seq);
  const Segment* seg_;
  mutable int ch_;
  std::string name_;
  mutable uint8_t* base_ = nullptr;
  mutable uint32_t generation_ = 0;
  mutable const polyloc_ring_control* ring_ = nullptr;
  mutable uint64_t next_ = 0;   // frame number to read next
  uint64_t overruns_ = 0, torn_ = 0;
};

template <class F> bool Reader::readInPlace(F&& f) {
  FrameInfo info;
  uint64_t seq = 0;
  const polyloc_slot_header* slot = locate(info, seq);
  if (!slot) return false;
  const FrameInfo& view = info;
  f(view, reinterpret_cast<const uint8_t*>(slot + 1));
  return confirm(slot, seq);
}

// The doorbell: every input channel's commit bumps it, so polylocd sleeps on one word for all
// its inputs:  seen = doorbell(seg); drain every reader; waitDoorbell(seg, seen, timeout).
uint32_t doorbell(const Segment& seg);
// True as soon as the doorbell differs from `seen` (at once if it does already), false on timeout.
bool waitDoorbell(const Segment& seg, uint32_t seen, int64_t timeout_ns);

}  // namespace polyloc::shm
