// The frame of the control protocol (docs/protocol.md): little-endian 32-bit words
//   magic "HELO" (0x4f4c4548) | size | command | data words ... | CRC-32
// size counts the whole frame in bytes, magic to CRC (16 + 4 * data words), so a reader knows
// from the first 8 bytes how much to wait for. The CRC is zlib's crc32 over every byte before it.
#pragma once

#include "protocol/commands.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace polyloc::protocol {

inline constexpr uint32_t kMagic = 0x4f4c4548;  // bytes 'H' 'E' 'L' 'O' on the wire
inline constexpr uint32_t kMinFrameBytes = 16;  // magic, size, command, CRC: no data
inline constexpr uint32_t kDefaultMaxFrameBytes = 64 * 1024;

inline constexpr size_t frameBytes(size_t data_words) { return kMinFrameBytes + 4 * data_words; }

struct Frame {
  uint32_t command = 0;
  std::vector<uint32_t> data;  // host order
  bool operator==(const Frame&) const = default;
};

uint32_t crc32(std::span<const uint8_t> bytes);  // zlib's (IEEE 802.3, reflected, ~0 in/out)

// Appends one complete frame to out.
void appendFrame(std::vector<uint8_t>& out, uint32_t command, std::span<const uint32_t> data);
std::vector<uint8_t> encodeFrame(uint32_t command, std::span<const uint32_t> data = {});
inline std::vector<uint8_t> encodeFrame(const Frame& f) { return encodeFrame(f.command, f.data); }

// A reply to `request`: command id with bit 31 set, data = status then the reply's words.
Frame makeReply(uint32_t request, Status status, std::span<const uint32_t> data = {});
inline Frame errorReply(uint32_t request, Status status) { return makeReply(request, status); }
// A connection-level error (frame error, timeout, busy): FRAME_ERROR, data = status, detail
// (BadCrc: the command word as read; BadFrameSize/FrameTooLarge: the size field; else 0).
Frame frameErrorReply(Status status, uint32_t detail = 0);

// The status word of a reply; BadSize for a reply without data (not a valid reply).
Status replyStatus(const Frame& reply);
// The words after the status.
std::span<const uint32_t> replyData(const Frame& reply);

// Little-endian word access on raw bytes (no alignment needed).
inline uint32_t loadLE32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
inline void storeLE32(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v), p[1] = uint8_t(v >> 8), p[2] = uint8_t(v >> 16), p[3] = uint8_t(v >> 24);
}

}  // namespace polyloc::protocol
