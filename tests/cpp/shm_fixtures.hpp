// Shared-memory test helpers: a segment name per test process (ctest runs tests in parallel),
// removed afterwards; the channel set of a small rig; frames whose every byte follows from the
// frame number, so a reader can tell an intact frame from a torn one.
#pragma once

#include "shm/channel.hpp"
#include "shm/segment.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace polyloc::test {

// "t<pid>-<suffix>": unique per process, unlinked by the destructor.
class ShmName {
 public:
  explicit ShmName(const std::string& suffix = "seg") : name_("t" + std::to_string(getpid()) + "-" + suffix) {
    shm::Segment::unlink(name_);
  }
  ~ShmName() {
    try {
      shm::Segment::unlink(name_);
    } catch (...) {
    }
  }
  ShmName(const ShmName&) = delete;
  ShmName& operator=(const ShmName&) = delete;
  const std::string& str() const { return name_; }
  operator const std::string&() const { return name_; }

 private:
  std::string name_;
};

inline shm::ChannelSpec spec(const std::string& name, uint32_t kind, uint32_t dir, uint32_t slots = 8,
                             uint32_t count = 0, uint32_t width = 0, uint32_t height = 0) {
  shm::ChannelSpec s;
  s.name = name;
  s.kind = kind;
  s.direction = dir;
  s.slot_count = slots;
  s.count = count;
  s.width = width;
  s.height = height;
  return s;
}

// One channel of raw frames of `bytes` bytes (the ring tests fill them with patterns).
inline std::vector<shm::ChannelSpec> blobChannel(uint32_t direction, uint32_t slots, uint32_t bytes) {
  shm::ChannelSpec s = spec("blob", POLYLOC_KIND_RANGES, direction, slots);
  s.payload_max = bytes;
  return {s};
}

// A scanner of 541 beams, a 64x50 ToF camera, odometry, and every output.
inline std::vector<shm::ChannelSpec> rigChannels() {
  return {spec("scan/front", POLYLOC_KIND_RANGES, POLYLOC_DIR_INPUT, 8, 541),
          spec("depth/tof", POLYLOC_KIND_DEPTH, POLYLOC_DIR_INPUT, 4, 0, 64, 50),
          spec("odom", POLYLOC_KIND_ODOMETRY, POLYLOC_DIR_INPUT, 32),
          spec("pose", POLYLOC_KIND_POSE, POLYLOC_DIR_OUTPUT, 8),
          spec("vrs", POLYLOC_KIND_VRS, POLYLOC_DIR_OUTPUT, 4, 360),
          spec("tracks", POLYLOC_KIND_TRACKS, POLYLOC_DIR_OUTPUT, 4),
          spec("health", POLYLOC_KIND_HEALTH, POLYLOC_DIR_OUTPUT, 2)};
}

// Frame n's payload: [n][n*golden + i for i...] as uint64 words, bytes long (a multiple of 8).
inline uint64_t patternWord(uint64_t frame, size_t i) { return frame * 0x9e3779b97f4a7c15ull + i * 0xbf58476d1ce4e5b9ull; }

inline void fillPattern(uint8_t* p, size_t bytes, uint64_t frame) {
  std::memcpy(p, &frame, sizeof frame);
  for (size_t i = 1; i < bytes / 8; ++i) {
    const uint64_t w = patternWord(frame, i);
    std::memcpy(p + 8 * i, &w, sizeof w);
  }
}

// True when p holds frame n's pattern (its first word says which frame it claims to be).
inline bool checkPattern(const uint8_t* p, size_t bytes, uint64_t frame) {
  uint64_t first = 0;
  std::memcpy(&first, p, sizeof first);
  if (first != frame) return false;
  for (size_t i = 1; i < bytes / 8; ++i) {
    uint64_t w = 0;
    std::memcpy(&w, p + 8 * i, sizeof w);
    if (w != patternWord(frame, i)) return false;
  }
  return true;
}

inline int64_t nowRealtimeNs() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

// The newest frame of polylocd's health channel, if any.
inline std::optional<polyloc_health> readHealth(const shm::Segment& seg) {
  shm::Reader r(seg, seg.find("health"), shm::Reader::Start::Newest);
  std::vector<uint8_t> buf;
  if (!r.newest(buf) || buf.size() < sizeof(polyloc_health)) return std::nullopt;
  polyloc_health h;
  std::memcpy(&h, buf.data(), sizeof h);
  return h;
}

}  // namespace polyloc::test
