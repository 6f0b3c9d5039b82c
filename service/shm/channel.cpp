// Writer and Reader: the seqlock protocol of docs/interface.md, "Writing a frame" and
// "Reading a frame". The payload is copied with memcpy between the seq checks; a copy that
// raced with the writer is detected by the second check and thrown away, never used.
#include "shm/channel.hpp"

#include "shm/atomic.hpp"
#include "shm/futex.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace polyloc::shm {
namespace {

using Errc = ShmError::Errc;

int64_t monotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

std::string nameOf(const polyloc_channel_desc& d) { return std::string(d.name, strnlen(d.name, POLYLOC_NAME_LEN)); }

std::string where(const Segment& seg, const std::string& channel) {
  return "channel '" + channel + "' of " + seg.name();
}

int findOrThrow(const Segment& seg, const std::string& name) {
  const int ch = seg.find(name);
  if (ch < 0) throw ShmError(Errc::NotFound, where(seg, name) + ": the re-attached segment has no such channel");
  return ch;
}

bool alive(int32_t pid) { return !(kill(pid, 0) == -1 && errno == ESRCH); }

// Deadline arithmetic with "no limit" (timeout < 0) and no overflow.
int64_t deadlineOf(int64_t timeout_ns) {
  return timeout_ns < 0 ? INT64_MAX : monotonicNs() + std::min<int64_t>(timeout_ns, INT64_MAX / 2);
}
// -1: no limit; 0: the deadline has passed.
int64_t remainingUntil(int64_t deadline) {
  return deadline == INT64_MAX ? -1 : std::max<int64_t>(0, deadline - monotonicNs());
}

}  // namespace

// ---- Writer ------------------------------------------------------------------------------------

Writer::Writer(Segment& seg, int channel, bool take_over) : seg_(&seg), ch_(channel) {
  name_ = nameOf(seg.channel(channel));
  bind();
  claim(take_over);
}

Writer::~Writer() {
  if (seg_->base() != base_) return;  // re-attached and never used since: nothing of ours there
  int32_t mine = pid_;
  atomic::compareExchange(&ring_->writer_pid, mine, int32_t{0});
}

void Writer::bind() {
  base_ = seg_->base();
  ring_ = seg_->ring(ch_);
  open_ = false;
}

void Writer::claim(bool take_over) {
  pid_ = getpid();
  for (;;) {
    int32_t holder = atomic::loadAcquire(&ring_->writer_pid);
    if (holder == pid_) break;
    if (holder != 0 && !take_over && alive(holder))
      throw ShmError(Errc::Busy, where(*seg_, name_) + ": the writer role is held by running process " +
                                     std::to_string(holder));
    // A dead holder (or a forced take-over): its unfinished frame, if any, is overwritten below.
    if (atomic::compareExchange(&ring_->writer_pid, holder, pid_)) {
      atomic::fetchAdd(&ring_->writer_claims, uint64_t{1});
      break;
    }
  }
  frame_ = atomic::loadAcquire(&ring_->write_count);
}

uint8_t* Writer::begin() {
  if (seg_->base() != base_) {  // re-attached: claim the channel of the new segment
    ch_ = findOrThrow(*seg_, name_);
    bind();
    claim(false);
  }
  if (open_) return reinterpret_cast<uint8_t*>(slot_ + 1);
  const int32_t holder = atomic::loadAcquire(&ring_->writer_pid);
  if (holder != pid_)
    throw ShmError(Errc::Busy, where(*seg_, name_) + ": the writer role was taken over by process " +
                                   std::to_string(holder));
  // The only writer: write_count is ours; after a dead writer it is where that one stopped.
  frame_ = atomic::loadRelaxed(&ring_->write_count);
  slot_ = seg_->slot(ch_, frame_);
  atomic::storeRelaxed(&slot_->seq, 2 * frame_ + 1);
  // The odd seq is visible before any byte of the payload changes.
  atomic::fenceRelease();
  open_ = true;
  return reinterpret_cast<uint8_t*>(slot_ + 1);
}

void Writer::commit(uint32_t bytes, int64_t stamp_ns) {
  if (!open_) throw std::logic_error(where(*seg_, name_) + ": commit() without begin()");
  const polyloc_channel_desc& d = seg_->channel(ch_);
  if (bytes > d.payload_max)
    throw std::length_error(where(*seg_, name_) + ": frame of " + std::to_string(bytes) + " bytes, capacity " +
                            std::to_string(d.payload_max));
  atomic::storeRelaxed(&slot_->size, bytes);
  atomic::storeRelaxed(&slot_->kind, d.kind);
  atomic::storeRelaxed(&slot_->stamp_ns, stamp_ns);
  atomic::storeRelaxed(&slot_->publish_ns, monotonicNs());
  atomic::storeRelease(&slot_->seq, 2 * frame_ + 2);
  atomic::storeRelease(&ring_->write_count, frame_ + 1);
  open_ = false;
  // Publish, then wake: a waiter that read the old notify value is woken, or its FUTEX_WAIT sees
  // the new one and returns at once.
  atomic::fetchAdd(&ring_->notify, 1u);
  futex::wakeAll(&ring_->notify);
  if (d.direction == POLYLOC_DIR_INPUT) {
    auto* bell = &reinterpret_cast<polyloc_shm_header*>(base_)->doorbell;
    atomic::fetchAdd(bell, 1u);
    futex::wakeAll(bell);
  }
}

void Writer::write(const void* payload, uint32_t bytes, int64_t stamp_ns) {
  // Checked before begin(): a refused frame leaves no odd seq behind.
  if (bytes > seg_->channel(ch_).payload_max)
    throw std::length_error(where(*seg_, name_) + ": frame of " + std::to_string(bytes) + " bytes, capacity " +
                            std::to_string(seg_->channel(ch_).payload_max));
  std::memcpy(begin(), payload, bytes);
  commit(bytes, stamp_ns);
}

uint64_t Writer::written() const { return atomic::loadAcquire(&ring_->write_count); }
const polyloc_channel_desc& Writer::channel() const { return seg_->channel(ch_); }

// ---- Reader ------------------------------------------------------------------------------------

Reader::Reader(const Segment& seg, int channel, Start start) : seg_(&seg), ch_(channel) {
  name_ = nameOf(seg.channel(channel));
  bind(start);
}

void Reader::bind(Start start) const {
  base_ = seg_->base();
  generation_ = seg_->generation();
  ring_ = seg_->ring(ch_);
  const uint64_t wc = atomic::loadAcquire(&ring_->write_count);
  const uint64_t n = seg_->channel(ch_).slot_count;
  switch (start) {
    case Start::Newest: next_ = wc ? wc - 1 : 0; break;
    case Start::Oldest: next_ = wc > n ? wc - n : 0; break;
    case Start::Next: next_ = wc; break;
  }
}

void Reader::rebindIfMoved() const {
  if (seg_->base() == base_) return;
  const bool same_data = seg_->generation() == generation_;
  const uint64_t next = next_;
  ch_ = findOrThrow(*seg_, name_);
  bind(Start::Oldest);  // a new generation: every frame in it is new to this reader
  if (same_data) next_ = next;
}

const polyloc_slot_header* Reader::locate(FrameInfo& info, uint64_t& seq) {
  rebindIfMoved();
  const uint64_t n = seg_->channel(ch_).slot_count;
  for (;;) {
    const uint64_t wc = atomic::loadAcquire(&ring_->write_count);
    if (next_ >= wc) return nullptr;
    if (wc - next_ > n) {  // lapped: what is left of the backlog is older than the newest
      overruns_ += wc - 1 - next_;
      next_ = wc - 1;
    }
    const polyloc_slot_header* slot = seg_->slot(ch_, next_);
    const uint64_t s = atomic::loadAcquire(&slot->seq);
    const uint64_t complete = 2 * next_ + 2;
    if (s == complete) {
      seq = s;
      info.frame = next_;
      info.size = atomic::loadRelaxed(&slot->size);
      info.kind = atomic::loadRelaxed(&slot->kind);
      info.stamp_ns = atomic::loadRelaxed(&slot->stamp_ns);
      info.publish_ns = atomic::loadRelaxed(&slot->publish_ns);
      return slot;
    }
    // Older than the frame: write_count and the slot disagree (only a broken ring does that).
    if (s < complete) return nullptr;
    // Newer: the frame was overwritten since write_count was read; it is lost.
    ++overruns_;
    ++next_;
  }
}

bool Reader::confirm(const polyloc_slot_header* slot, uint64_t seq) {
  // Every read of the slot above happens before the seq is read again.
  atomic::fenceAcquire();
  if (atomic::loadRelaxed(&slot->seq) == seq) {
    ++next_;
    return true;
  }
  ++torn_;
  return false;
}

std::optional<FrameInfo> Reader::next(std::vector<uint8_t>& payload) {
  rebindIfMoved();
  const uint32_t cap = seg_->channel(ch_).payload_max;
  // Each failed try loses the frame to the writer and moves on, so the loop ends; the bound
  // only keeps a reader that is always lapped (a huge frame copied slowly) from spinning.
  for (int tries = 0; tries < 16; ++tries) {
    FrameInfo info;
    uint64_t seq = 0;
    const polyloc_slot_header* slot = locate(info, seq);
    if (!slot) return std::nullopt;
    payload.resize(std::min(info.size, cap));
    std::memcpy(payload.data(), slot + 1, payload.size());
    if (confirm(slot, seq)) return info;
  }
  return std::nullopt;
}

std::optional<FrameInfo> Reader::newest(std::vector<uint8_t>& payload) {
  rebindIfMoved();
  for (int tries = 0; tries < 16; ++tries) {
    const uint64_t wc = atomic::loadAcquire(&ring_->write_count);
    if (wc == 0) return std::nullopt;
    next_ = wc - 1;  // a deliberate skip, not an overrun
    if (auto f = next(payload)) return f;
  }
  return std::nullopt;
}

bool Reader::wait(int64_t timeout_ns, int64_t spin_ns) {
  rebindIfMoved();
  const auto ready = [&] { return atomic::loadAcquire(&ring_->write_count) > next_; };
  if (ready()) return true;
  if (timeout_ns == 0) return false;
  const int64_t deadline = deadlineOf(timeout_ns);
  if (spin_ns > 0) {
    const int64_t spin_end = std::min(deadline, monotonicNs() + spin_ns);
    do {
      for (int i = 0; i < 64; ++i) {
        if (ready()) return true;
        atomic::cpuRelax();
      }
    } while (monotonicNs() < spin_end);
  }
  for (;;) {
    // notify before write_count: a frame published after this load changes notify, so the
    // FUTEX_WAIT below returns at once instead of sleeping through it.
    const uint32_t seen = atomic::loadAcquire(&ring_->notify);
    if (ready()) return true;
    const int64_t left = remainingUntil(deadline);
    if (left == 0) return false;
    futex::wait(&ring_->notify, seen, left);
  }
}

uint64_t Reader::available() const {
  rebindIfMoved();
  const uint64_t wc = atomic::loadAcquire(&ring_->write_count);
  return wc > next_ ? std::min<uint64_t>(wc - next_, seg_->channel(ch_).slot_count) : 0;
}

uint64_t Reader::overruns() const { return overruns_; }
uint64_t Reader::torn() const { return torn_; }
const polyloc_channel_desc& Reader::channel() const {
  rebindIfMoved();
  return seg_->channel(ch_);
}

// ---- Doorbell ----------------------------------------------------------------------------------

uint32_t doorbell(const Segment& seg) { return atomic::loadAcquire(&seg.header().doorbell); }

bool waitDoorbell(const Segment& seg, uint32_t seen, int64_t timeout_ns) {
  const uint32_t* bell = &seg.header().doorbell;
  const int64_t deadline = deadlineOf(timeout_ns);
  for (;;) {
    if (atomic::loadAcquire(bell) != seen) return true;
    const int64_t left = remainingUntil(deadline);
    if (left == 0) return false;
    futex::wait(bell, seen, left);
  }
}

}  // namespace polyloc::shm
