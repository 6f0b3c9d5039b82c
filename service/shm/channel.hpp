// Writing and reading one channel of a segment (seqlock slots, see bindings/c/polyloc_shm.h).
// A writer never waits for readers; any number of readers read in place at their own speed.
//
//   shm::Writer w(seg, seg.find("scan/front"));          // claims the writer role
//   auto* p = w.begin();  ...fill p (payload_max bytes)...;  w.commit(bytes, stamp_ns);
//
//   shm::Reader r(seg, seg.find("pose"));                 // starts after the newest frame
//   while (r.wait(100'000'000)) while (auto f = r.next(buf)) use(*f, buf);
#pragma once

#include "shm/segment.hpp"

#include <cstdint>
#include <optional>
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

  // The payload area of the next frame's slot (seq set odd): payload_max bytes.
  uint8_t* begin();
  // Completes the frame begun: seq even, write_count + 1, futex wake. bytes <= payload_max.
  void commit(uint32_t bytes, int64_t stamp_ns);
  // begin + memcpy + commit. Throws std::length_error when bytes > payload_max.
  void write(const void* payload, uint32_t bytes, int64_t stamp_ns);
  uint64_t written() const;   // frames committed on the channel

 private:
  Segment* seg_;
  int ch_;
  uint64_t frame_ = 0;
  bool open_ = false;
};

struct FrameInfo {
  uint64_t frame = 0;       // its number on the channel
  uint32_t size = 0;        // payload bytes
  uint32_t kind = 0;
  int64_t stamp_ns = 0, publish_ns = 0;
};

class Reader {
 public:
  enum class Start { Newest, Oldest, Next };  // Newest: the last published frame is read first; Next: only frames after attaching
  Reader(const Segment& seg, int channel, Start start = Start::Next);

  // The next unread frame copied into `payload` (resized); nullopt when none is new. After an
  // overrun (the writer lapped this reader) skips to the newest frame and counts it.
  std::optional<FrameInfo> next(std::vector<uint8_t>& payload);
  // The newest complete frame (skips everything older), copied; nullopt when none.
  std::optional<FrameInfo> newest(std::vector<uint8_t>& payload);
  // In place: f(const FrameInfo&, const uint8_t* payload) is called on the slot memory, then the
  // slot's seq is re-checked; returns false (and f's work must be discarded) when the frame was
  // overwritten while f ran. Advances like next().
  template <class F> bool readInPlace(F&& f);

  // Blocks until a frame newer than the last read is published or timeout (ns; FUTEX_WAIT on the
  // ring's notify word); true when one is there. timeout 0: poll.
  bool wait(int64_t timeout_ns);
  uint64_t available() const;   // published frames not yet read (capped at slot_count)
  uint64_t overruns() const;    // frames lost to overruns
  uint64_t torn() const;        // reads retried because the writer overwrote the slot meanwhile

 private:
  const Segment* seg_;
  int ch_;
  uint64_t next_ = 0;           // frame number to read next
  uint64_t overruns_ = 0, torn_ = 0;
};

}  // namespace polyloc::shm
